#include "mgelastic/grid/residual.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "mgelastic/grid/stencil.hpp"

namespace mgelastic::grid {
namespace {

// Momentum residual of u_axis at k, zero where the band (or nothing) owns the equation.
template <int Dim, typename Scalar, int Axis>
Scalar momentum_residual(const std::array<const Scalar*, Dim>& u, const Scalar* p,
                         const std::array<std::ptrdiff_t, Dim>& s,
                         const StencilConstants<Dim, Scalar>& c, Relaxation relax, Scalar b,
                         Scalar inertia, std::ptrdiff_t k) {
  return relax == Relaxation::DISTRIBUTIVE
             ? b - momentum_row<Dim, Scalar, Axis>(u, p, s, k, c) + inertia * u[Axis][k]
             : Scalar(0);
}

// Stencil residuals of every field in one pass: each momentum row reads every u_j and p, so
// one pass streams x once instead of once per field (Dim + 1 times).
template <int Dim, typename Scalar>
void stencil_residual(Level<Dim, Scalar>& level, const std::array<const Scalar*, Dim>& u,
                      const std::array<std::ptrdiff_t, Dim>& s,
                      const StencilConstants<Dim, Scalar>& c) {
  std::array<const Relaxation*, Dim + 1> relax;
  std::array<const Scalar*, Dim + 1> b;
  std::array<Scalar*, Dim + 1> r;
  for (int f = 0; f <= Dim; ++f) {
    relax[f] = level.relaxation[f].data();
    b[f] = level.b[f].data();
    r[f] = level.r[f].data();
  }
  const Scalar* p = level.x[Dim].data();
  const Scalar inertia = level.inertia;
  const Scalar mu = level.mu, lambda = level.lambda;
  const bool has_pressure = lambda > 0;
  const Scalar d = has_pressure ? mu * mu / lambda : Scalar(0);
  const auto n = static_cast<std::ptrdiff_t>(level.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t k = 0; k < n; ++k) {
    r[0][k] = momentum_residual<Dim, Scalar, 0>(u, p, s, c, relax[0][k], b[0][k], inertia, k);
    r[1][k] = momentum_residual<Dim, Scalar, 1>(u, p, s, c, relax[1][k], b[1][k], inertia, k);
    if constexpr (Dim == 3)
      r[2][k] = momentum_residual<Dim, Scalar, 2>(u, p, s, c, relax[2][k], b[2][k], inertia, k);
    r[Dim][k] = relax[Dim][k] == Relaxation::DISTRIBUTIVE && has_pressure
                    ? b[Dim][k] - mu * divergence<Dim, Scalar>(u, s, k, c.inv_h) - d * p[k]
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
void update_residual(Level<Dim, Scalar>& level) {
  std::array<const Scalar*, Dim> u;
  std::array<std::ptrdiff_t, Dim> s;
  for (int i = 0; i < Dim; ++i) {
    u[i] = level.x[i].data();
    s[i] = level.lattice.stride(i);
  }
  const Scalar inv_h = static_cast<Scalar>(1.0 / level.lattice.h);
  const StencilConstants<Dim, Scalar> c{level.mu, inv_h, inv_h * inv_h};
  stencil_residual<Dim, Scalar>(level, u, s, c);
  band_residual(level);
}

template <int Dim, typename Scalar>
double compute_residual(Level<Dim, Scalar>& level) {
  update_residual(level);
  return residual_norm(level);
}

template <int Dim, typename Scalar>
double residual_norm(const Level<Dim, Scalar>& level) {
  // Partial sums over fixed chunks in parallel, added in chunk order: the same value for any
  // thread count.
  constexpr std::ptrdiff_t chunk = 1 << 14;
  const auto n = static_cast<std::ptrdiff_t>(level.size());
  const std::ptrdiff_t chunks_per_field = (n + chunk - 1) / chunk;
  std::vector<double> partial(static_cast<std::size_t>(chunks_per_field * (Dim + 1)));
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t q = 0; q < static_cast<std::ptrdiff_t>(partial.size()); ++q) {
    const Scalar* r = level.r[q / chunks_per_field].data();
    const std::ptrdiff_t begin = (q % chunks_per_field) * chunk;
    const std::ptrdiff_t end = std::min(begin + chunk, n);
    double sum = 0.0;
    for (std::ptrdiff_t k = begin; k < end; ++k) sum += static_cast<double>(r[k]) * r[k];
    partial[q] = sum;
  }
  double sum = 0.0;
  for (double value : partial) sum += value;
  return std::sqrt(sum);
}

#define MGELASTIC_INSTANTIATE(D, S)                     \
  template void update_residual<D, S>(Level<D, S>&);    \
  template double compute_residual<D, S>(Level<D, S>&); \
  template double residual_norm<D, S>(const Level<D, S>&);
MGELASTIC_INSTANTIATE(2, float)
MGELASTIC_INSTANTIATE(2, double)
MGELASTIC_INSTANTIATE(3, float)
MGELASTIC_INSTANTIATE(3, double)
#undef MGELASTIC_INSTANTIATE

}  // namespace mgelastic::grid
