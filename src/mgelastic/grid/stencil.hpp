#pragma once
// Uniform interior stencils of the augmented system (5) in displacement form (Sec. 4.1, 5.3):
//   momentum (at u_i faces):  L_i(u, p) = sum_j d_j P_ij,  P_ii = 2 mu d_i u_i - mu p,
//                                                         P_ij = mu (d_j u_i + d_i u_j)
//   pressure (at cells):      L_p(u, p) = mu div u + (mu^2 / lambda) p
// with central differences over one cell (Sec. 3). Layout: see lattice.hpp; `u[i]` points to the
// u_i array, `p` to the pressure array, all of the lattice's padded size; `s[a]` are strides.
// These are used only where every stencil variable is an interior or Dirichlet variable; rows
// touching traction boundaries are stored explicitly (band_rows.hpp).
#include <array>
#include <cstddef>

namespace mgelastic::grid {

template <int Dim, typename Scalar>
struct StencilConstants {
  Scalar mu, inv_h, inv_h2;
};

// Value of the momentum operator row of u_axis at face k.
template <int Dim, typename Scalar, int Axis>
inline Scalar momentum_row(const std::array<const Scalar*, Dim>& u, const Scalar* p,
                           const std::array<std::ptrdiff_t, Dim>& s, std::ptrdiff_t k,
                           const StencilConstants<Dim, Scalar>& c) {
  const Scalar* ui = u[Axis];
  const std::ptrdiff_t si = s[Axis];
  // d_i P_ii: second difference of u_i along i (weight 2 mu) and the pressure gradient.
  Scalar value = Scalar(2) * c.mu * c.inv_h2 * (ui[k + si] - Scalar(2) * ui[k] + ui[k - si]) -
                 c.mu * c.inv_h * (p[k] - p[k - si]);
  for (int j = 0; j < Dim; ++j) {
    if (j == Axis) continue;
    const std::ptrdiff_t sj = s[j];
    const Scalar* uj = u[j];
    // d_j P_ij: second difference of u_i along j and the mixed difference of u_j.
    value += c.mu * c.inv_h2 *
             ((ui[k + sj] - Scalar(2) * ui[k] + ui[k - sj]) +
              (uj[k + sj] - uj[k + sj - si] - uj[k] + uj[k - si]));
  }
  return value;
}

// Divergence of u at cell k (one-cell central differences).
template <int Dim, typename Scalar>
inline Scalar divergence(const std::array<const Scalar*, Dim>& u,
                         const std::array<std::ptrdiff_t, Dim>& s, std::ptrdiff_t k, Scalar inv_h) {
  Scalar div = 0;
  for (int i = 0; i < Dim; ++i) div += u[i][k + s[i]] - u[i][k];
  return div * inv_h;
}

}  // namespace mgelastic::grid
