#include "mgelastic/grid/residual.hpp"

#include <cmath>

#include "mgelastic/grid/stencil.hpp"

namespace mgelastic::grid {
namespace {

template <int Dim, typename Scalar, int Axis>
void momentum_residual(Level<Dim, Scalar>& level, const std::array<const Scalar*, Dim>& u,
                       const std::array<std::ptrdiff_t, Dim>& s,
                       const StencilConstants<Dim, Scalar>& c) {
  const Relaxation* relax = level.relaxation[Axis].data();
  const Scalar* b = level.b[Axis].data();
  Scalar* r = level.r[Axis].data();
  const Scalar* p = level.x[Dim].data();
  const Scalar inertia = level.inertia;
  const auto n = static_cast<std::ptrdiff_t>(level.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t k = 0; k < n; ++k) {
    r[k] = relax[k] == Relaxation::DISTRIBUTIVE
               ? b[k] - momentum_row<Dim, Scalar, Axis>(u, p, s, k, c) + inertia * u[Axis][k]
               : Scalar(0);
  }
}

template <int Dim, typename Scalar>
void pressure_residual(Level<Dim, Scalar>& level, const std::array<const Scalar*, Dim>& u,
                       const std::array<std::ptrdiff_t, Dim>& s,
                       const StencilConstants<Dim, Scalar>& c) {
  const Relaxation* relax = level.relaxation[Dim].data();
  const Scalar* b = level.b[Dim].data();
  const Scalar* p = level.x[Dim].data();
  Scalar* r = level.r[Dim].data();
  const Scalar mu = level.mu, lambda = level.lambda;
  const Scalar d = lambda > 0 ? mu * mu / lambda : Scalar(0);
  const auto n = static_cast<std::ptrdiff_t>(level.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t k = 0; k < n; ++k) {
    r[k] = relax[k] == Relaxation::DISTRIBUTIVE && lambda > 0
               ? b[k] - mu * divergence<Dim, Scalar>(u, s, k, c.inv_h) - d * p[k]
               : Scalar(0);
  }
}

template <int Dim, typename Scalar>
void band_residual(Level<Dim, Scalar>& level) {
  auto row_value = [&](const SparseRows<Scalar>& rows, std::ptrdiff_t m) {
    Scalar sum = 0;
    for (std::uint32_t e = rows.start[m]; e < rows.start[m + 1]; ++e)
      sum += rows.value[e] * level.x[rows.column_field[e]][rows.column_index[e]];
    return sum;
  };
  const auto& u_rows = level.band_u;
  const auto u_count = static_cast<std::ptrdiff_t>(u_rows.rows());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t m = 0; m < u_count; ++m) {
    const int f = u_rows.target_field[m];
    const std::uint32_t k = u_rows.target_index[m];
    level.r[f][k] = level.b[f][k] - u_rows.constant[m] - row_value(u_rows, m);
  }
  if (level.lambda <= 0) return;
  const auto& p_rows = level.band_p;
  const Scalar d0 = level.mu * level.mu / level.lambda;
  const auto p_count = static_cast<std::ptrdiff_t>(p_rows.rows());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t m = 0; m < p_count; ++m) {
    const std::uint32_t k = p_rows.target_index[m];
    level.r[Dim][k] = level.b[Dim][k] - p_rows.constant[m] - row_value(p_rows, m) -
                      (d0 + level.band_p_extra[m]) * level.x[Dim][k];
  }
}

}  // namespace

template <int Dim, typename Scalar>
double compute_residual(Level<Dim, Scalar>& level) {
  std::array<const Scalar*, Dim> u;
  std::array<std::ptrdiff_t, Dim> s;
  for (int i = 0; i < Dim; ++i) {
    u[i] = level.x[i].data();
    s[i] = level.lattice.stride(i);
  }
  const Scalar inv_h = static_cast<Scalar>(1.0 / level.lattice.h);
  const StencilConstants<Dim, Scalar> c{level.mu, inv_h, inv_h * inv_h};
  momentum_residual<Dim, Scalar, 0>(level, u, s, c);
  momentum_residual<Dim, Scalar, 1>(level, u, s, c);
  if constexpr (Dim == 3) momentum_residual<Dim, Scalar, 2>(level, u, s, c);
  pressure_residual<Dim, Scalar>(level, u, s, c);
  band_residual(level);
  return residual_norm(level);
}

template <int Dim, typename Scalar>
double residual_norm(const Level<Dim, Scalar>& level) {
  double sum = 0.0;
  for (int i = 0; i < Dim; ++i)
    for (Scalar v : level.r[i]) sum += static_cast<double>(v) * v;
  for (Scalar v : level.r[Dim]) sum += static_cast<double>(v) * v;
  return std::sqrt(sum);
}

#define MGELASTIC_INSTANTIATE(D, S)                     \
  template double compute_residual<D, S>(Level<D, S>&); \
  template double residual_norm<D, S>(const Level<D, S>&);
MGELASTIC_INSTANTIATE(2, float)
MGELASTIC_INSTANTIATE(2, double)
MGELASTIC_INSTANTIATE(3, float)
MGELASTIC_INSTANTIATE(3, double)
#undef MGELASTIC_INSTANTIATE

}  // namespace mgelastic::grid
