#include "mgelastic/grid/distributive_smoother.hpp"

#include "mgelastic/grid/stencil.hpp"

namespace mgelastic::grid {
namespace {

template <int Dim, typename Scalar>
struct Views {
  std::array<Scalar*, Dim> u;
  std::array<const Scalar*, Dim> u_const;
  Scalar* p;
  std::array<std::ptrdiff_t, Dim> s;
  StencilConstants<Dim, Scalar> c;

  explicit Views(Level<Dim, Scalar>& level) {
    for (int i = 0; i < Dim; ++i) {
      u[i] = level.x[i].data();
      u_const[i] = u[i];
      s[i] = level.lattice.stride(i);
    }
    p = level.x[Dim].data();
    const Scalar inv_h = static_cast<Scalar>(1.0 / level.lattice.h);
    c = {level.mu, inv_h, inv_h * inv_h};
  }
};

// Visits every lattice point, color by color; the blocks of one color run in parallel.
template <int Dim, typename Scalar, typename F>
void for_each_colored_block(const Level<Dim, Scalar>& level, F&& visit) {
  for (const auto& color : level.blocks.colors) {
    const auto count = static_cast<std::ptrdiff_t>(color.size());
#pragma omp parallel for schedule(dynamic, 1)
    for (std::ptrdiff_t b = 0; b < count; ++b) for_each_in_block(level.lattice, color[b], visit);
  }
}

template <int Dim, typename Scalar, int Axis>
void sweep_momentum(Level<Dim, Scalar>& level, Views<Dim, Scalar>& v) {
  const Relaxation* relax = level.relaxation[Axis].data();
  const Scalar* b = level.b[Axis].data();
  // At lambda = 0 the pressure vanishes identically (it is eliminated exactly) and the step is
  // plain Gauss-Seidel on the momentum row, whose diagonal is -(2d + 2) mu / h^2 - c.
  const bool pressure_free = level.lambda <= 0;
  const Scalar c = level.inertia;
  const Scalar inv_diagonal =
      Scalar(-1) / (Scalar(pressure_free ? 2 * Dim + 2 : 2 * Dim) * v.c.mu * v.c.inv_h2 + c);
  const Scalar p_step = pressure_free ? Scalar(0) : v.c.inv_h;
  const std::ptrdiff_t si = v.s[Axis];
  for_each_colored_block(level, [&](std::ptrdiff_t k) {
    if (relax[k] != Relaxation::DISTRIBUTIVE) return;
    const Scalar r =
        b[k] - momentum_row<Dim, Scalar, Axis>(v.u_const, v.p, v.s, k, v.c) + c * v.u[Axis][k];
    const Scalar delta = r * inv_diagonal;
    v.u[Axis][k] += delta;
    v.p[k] -= delta * p_step;
    v.p[k - si] += delta * p_step;
  });
}

// q step next to Dirichlet cells: the distribution moves only interior faces and interior
// pressures, so (LM)_pp = (mu n_faces + 4 d D) / h^2 + D c / mu with n_faces the faces it moves
// and D = mu^2 / lambda.
template <int Dim, typename Scalar>
void restricted_pressure_step(Level<Dim, Scalar>& level, Views<Dim, Scalar>& v, std::ptrdiff_t k,
                              Scalar residual_times_lambda) {
  const Scalar mu = level.mu, lambda = level.lambda;
  const auto& cells = level.cells;
  int moved = 0;
  for (int i = 0; i < Dim; ++i) {
    moved += cells[k - v.s[i]] == CellType::INTERIOR;
    moved += cells[k + v.s[i]] == CellType::INTERIOR;
  }
  const Scalar delta =
      residual_times_lambda /
      ((lambda * mu * Scalar(moved) + Scalar(4 * Dim) * mu * mu) * v.c.inv_h2 + mu * level.inertia);
  const Scalar du = delta * v.c.inv_h;
  for (int i = 0; i < Dim; ++i) {
    if (cells[k + v.s[i]] == CellType::INTERIOR) {
      v.u[i][k + v.s[i]] += du;
      v.p[k + v.s[i]] -= 2 * delta * v.c.inv_h2;
    }
    if (cells[k - v.s[i]] == CellType::INTERIOR) {
      v.u[i][k] -= du;
      v.p[k - v.s[i]] -= 2 * delta * v.c.inv_h2;
    }
  }
  v.p[k] += (Scalar(4 * Dim) * v.c.inv_h2 + level.inertia / mu) * delta;
}

template <int Dim, typename Scalar>
bool all_neighbors_interior(const Level<Dim, Scalar>& level, const Views<Dim, Scalar>& v,
                            std::ptrdiff_t k) {
  for (int i = 0; i < Dim; ++i) {
    if (level.cells[k - v.s[i]] != CellType::INTERIOR) return false;
    if (level.cells[k + v.s[i]] != CellType::INTERIOR) return false;
  }
  return true;
}

template <int Dim, typename Scalar>
void sweep_pressure(Level<Dim, Scalar>& level, Views<Dim, Scalar>& v) {
  const Relaxation* relax = level.relaxation[Dim].data();
  const Scalar* b = level.b[Dim].data();
  const Scalar mu = level.mu, lambda = level.lambda;
  // delta = r_p / (LM)_pp with numerator and denominator multiplied by lambda, so that the step
  // stays finite for small lambda.
  const Scalar inv_denominator =
      Scalar(1) / (mu * (lambda + 2 * mu) * Scalar(2 * Dim) * v.c.inv_h2 + mu * level.inertia);
  const Scalar p_center = Scalar(4 * Dim) * v.c.inv_h2 + level.inertia / mu;
  for_each_colored_block(level, [&](std::ptrdiff_t k) {
    if (relax[k] != Relaxation::DISTRIBUTIVE) return;
    const Scalar div = divergence<Dim, Scalar>(v.u_const, v.s, k, v.c.inv_h);
    const Scalar scaled_residual = lambda * (b[k] - mu * div) - mu * mu * v.p[k];
    if (!all_neighbors_interior(level, v, k)) {
      restricted_pressure_step(level, v, k, scaled_residual);
      return;
    }
    const Scalar delta = scaled_residual * inv_denominator;
    const Scalar du = delta * v.c.inv_h;
    for (int i = 0; i < Dim; ++i) {
      v.u[i][k + v.s[i]] += du;
      v.u[i][k] -= du;
      v.p[k + v.s[i]] -= 2 * delta * v.c.inv_h2;
      v.p[k - v.s[i]] -= 2 * delta * v.c.inv_h2;
    }
    v.p[k] += p_center * delta;
  });
}

}  // namespace

template <int Dim, typename Scalar>
void distributive_sweep(Level<Dim, Scalar>& level) {
  Views<Dim, Scalar> v(level);
  sweep_momentum<Dim, Scalar, 0>(level, v);
  sweep_momentum<Dim, Scalar, 1>(level, v);
  if constexpr (Dim == 3) sweep_momentum<Dim, Scalar, 2>(level, v);
  if (level.lambda > 0) sweep_pressure(level, v);
}

template void distributive_sweep<2, float>(Level<2, float>&);
template void distributive_sweep<2, double>(Level<2, double>&);
template void distributive_sweep<3, float>(Level<3, float>&);
template void distributive_sweep<3, double>(Level<3, double>&);

}  // namespace mgelastic::grid
