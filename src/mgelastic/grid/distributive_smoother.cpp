#include "mgelastic/grid/distributive_smoother.hpp"

#include <algorithm>

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

// Lexicographic Gauss-Seidel along an x-row is a recurrence only through the row's previous
// step: a step moves exactly one value the next point's residual reads, by a fixed multiple of
// its delta. So each segment is relaxed in three passes: the residuals of all points from the
// values before the segment (vectorized), the scalar recurrence
//   delta_x = (r_x - coupling * delta_{x-1}) / diagonal,
// and the distribution of all deltas (vectorized). The deltas equal those of the point-by-point
// sweep up to round-off. Segments are cut into chunks of at most kRowChunk points; a chunk's
// residuals are computed after the previous chunk moved, so nothing carries over.
constexpr int kRowChunk = 32;

// Whether a chunk holds an equation to relax: outside an embedded body (most of its bounding box)
// whole chunks are Dirichlet or exterior, and skipping them saves their residuals and their
// delta chain (all of whose steps would be zero).
inline bool any_relaxed(const VarCode* codes, int n, int field) {
  return any_relaxation(codes, n, field, Relaxation::DISTRIBUTIVE);
}

// The psi_Axis steps of one x-row segment (operator()), with the level's constants.
template <int Dim, typename Scalar, int Axis>
struct MomentumRows {
  const Views<Dim, Scalar>& v;
  const VarCode* codes;
  const Scalar* b;
  Scalar c, inv_diagonal, p_step, g_relaxed;
  std::ptrdiff_t si;

  MomentumRows(const Level<Dim, Scalar>& level, const Views<Dim, Scalar>& views)
      : v(views), codes(level.codes.data()), b(level.b[Axis].data()) {
    // At lambda = 0 the pressure vanishes identically (it is eliminated exactly) and the step is
    // plain Gauss-Seidel on the momentum row, whose diagonal is -(2d + 2) mu / h^2 - c.
    const bool pressure_free = level.lambda <= 0;
    c = level.inertia;
    inv_diagonal =
        Scalar(-1) / (Scalar(pressure_free ? 2 * Dim + 2 : 2 * Dim) * v.c.mu * v.c.inv_h2 + c);
    p_step = pressure_free ? Scalar(0) : v.c.inv_h;
    // The previous face's step changes this face's row by coupling * delta: through u_i[k - 1]
    // (weight 2 mu / h^2 along x for u_x, mu / h^2 otherwise) and, for u_x, p[k - 1].
    const Scalar coupling = Axis == 0
                                ? Scalar(2) * v.c.mu * v.c.inv_h2 - v.c.mu * v.c.inv_h * p_step
                                : v.c.mu * v.c.inv_h2;
    g_relaxed = -coupling * inv_diagonal;
    si = v.s[Axis];
  }

  void operator()(std::ptrdiff_t row, int length) const {
    Scalar* __restrict ui = v.u[Axis];
    Scalar* __restrict p = v.p;
    for (int first = 0; first < length; first += kRowChunk) {
      const std::ptrdiff_t k0 = row + first;
      const int n = std::min(kRowChunk, length - first);
      if (!any_relaxed(codes + k0, n, Axis)) continue;
      Scalar r[kRowChunk];
      for (int x = 0; x < n; ++x)
        r[x] = b[k0 + x] - momentum_row<Dim, Scalar, Axis>(v.u_const, p, v.s, k0 + x, v.c) +
               c * ui[k0 + x];
      // delta_x = relaxed_x (r_x - coupling delta_{x-1}) / diagonal = a_x + g_x delta_{x-1}
      // with a and g from a vectorized pass, so the serial chain is one fused multiply-add per
      // point on a register; written as (r - coupling delta) * inverse through delta[x] it was
      // a store-to-load forward, a multiply-add and a multiply per point, a third of the sweep.
      Scalar a[kRowChunk], g[kRowChunk];
#pragma omp simd
      for (int x = 0; x < n; ++x) {
        const bool relaxed = relaxation_of(codes[k0 + x], Axis) == Relaxation::DISTRIBUTIVE;
        a[x] = relaxed ? r[x] * inv_diagonal : Scalar(0);
        g[x] = relaxed ? g_relaxed : Scalar(0);
      }
      // delta[x + 1] is the step of point x; delta[0] and delta[n + 1] border the chunk.
      Scalar delta[kRowChunk + 2];
      delta[0] = 0;
      Scalar previous = 0;
      for (int x = 0; x < n; ++x) {
        previous = a[x] + g[x] * previous;
        delta[x + 1] = previous;
      }
      delta[n + 1] = 0;
#pragma omp simd
      for (int x = 0; x < n; ++x) ui[k0 + x] += delta[x + 1];
      if constexpr (Axis == 0) {
        // p[k] -= delta_k p_step and p[k - 1] += delta_k p_step, gathered per p[j].
        p[k0 - 1] += delta[1] * p_step;
#pragma omp simd
        for (int x = 0; x < n; ++x) p[k0 + x] += (delta[x + 2] - delta[x + 1]) * p_step;
      } else {
#pragma omp simd
        for (int x = 0; x < n; ++x) {
          p[k0 + x] -= delta[x + 1] * p_step;
          p[k0 + x - si] += delta[x + 1] * p_step;
        }
      }
    }
  }
};

// q step next to Dirichlet cells: the distribution moves only interior faces and interior
// pressures, so (LM)_pp = (mu n_faces + 4 d D) / h^2 + D c / mu with n_faces the faces it moves
// and D = mu^2 / lambda. Returns the step's delta for the residual times lambda.
template <int Dim, typename Scalar>
Scalar restricted_pressure_delta(const Level<Dim, Scalar>& level, const Views<Dim, Scalar>& v,
                                 std::ptrdiff_t k, Scalar residual_times_lambda) {
  const Scalar mu = level.mu, lambda = level.lambda;
  int moved = 0;
  for (int i = 0; i < Dim; ++i) {
    moved += level.cells[k - v.s[i]] == CellType::INTERIOR;
    moved += level.cells[k + v.s[i]] == CellType::INTERIOR;
  }
  return residual_times_lambda /
         ((lambda * mu * Scalar(moved) + Scalar(4 * Dim) * mu * mu) * v.c.inv_h2 +
          mu * level.inertia);
}

template <int Dim, typename Scalar>
void restricted_pressure_move(const Level<Dim, Scalar>& level, const Views<Dim, Scalar>& v,
                              std::ptrdiff_t k, Scalar delta) {
  const auto& cells = level.cells;
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
  v.p[k] += (Scalar(4 * Dim) * v.c.inv_h2 + level.inertia / v.c.mu) * delta;
}

template <int Dim, typename Scalar>
bool all_neighbors_interior(const Level<Dim, Scalar>& level, const Views<Dim, Scalar>& v,
                            std::ptrdiff_t k) {
  bool all = true;
  for (int i = 0; i < Dim; ++i) {
    all &= level.cells[k - v.s[i]] == CellType::INTERIOR;
    all &= level.cells[k + v.s[i]] == CellType::INTERIOR;
  }
  return all;
}

// The q steps of one row chunk (see sweep_momentum for the three passes). The previous cell's
// step moves u_x[k] by delta/h and p[k] by -2 delta/h^2, which raises this cell's residual
// (times lambda) by (lambda mu + 2 mu^2) delta / h^2, whether its step is restricted or not.
template <int Dim, typename Scalar>
void relax_pressure_chunk(const Level<Dim, Scalar>& level, const Views<Dim, Scalar>& v,
                          std::ptrdiff_t k0, int n) {
  const VarCode* codes = level.codes.data();
  if (!any_relaxed(codes + k0, n, Dim)) return;
  const Scalar* b = level.b[Dim].data();
  const Scalar mu = level.mu, lambda = level.lambda;
  // delta = r_p / (LM)_pp with numerator and denominator multiplied by lambda, so that the step
  // stays finite for small lambda.
  const Scalar inv_denominator =
      Scalar(1) / (mu * (lambda + 2 * mu) * Scalar(2 * Dim) * v.c.inv_h2 + mu * level.inertia);
  const Scalar p_center = Scalar(4 * Dim) * v.c.inv_h2 + level.inertia / mu;
  const Scalar coupling = (lambda * mu + 2 * mu * mu) * v.c.inv_h2;
  const Scalar* p_const = v.p;
  Scalar r[kRowChunk];
  bool regular[kRowChunk];
  for (int x = 0; x < n; ++x) {
    const Scalar div = divergence<Dim, Scalar>(v.u_const, v.s, k0 + x, v.c.inv_h);
    r[x] = lambda * (b[k0 + x] - mu * div) - mu * mu * p_const[k0 + x];
    regular[x] = all_neighbors_interior(level, v, k0 + x);
  }
  // delta[x + 1]: step of cell x, zero where restricted (moved afterwards, point by point).
  Scalar delta[kRowChunk + 2];
  Scalar restricted[kRowChunk];
  // As in sweep_momentum: a regular step is a + g * previous (one fused multiply-add on the
  // serial chain); the rare restricted cells compute their exact (LM)_pp off that path.
  Scalar a[kRowChunk], g[kRowChunk];
  bool relaxed[kRowChunk];
  const Scalar g_regular = coupling * inv_denominator;
#pragma omp simd
  for (int x = 0; x < n; ++x) {
    relaxed[x] = relaxation_of(codes[k0 + x], Dim) == Relaxation::DISTRIBUTIVE;
    a[x] = relaxed[x] && regular[x] ? r[x] * inv_denominator : Scalar(0);
    g[x] = relaxed[x] && regular[x] ? g_regular : Scalar(0);
  }
  delta[0] = 0;
  Scalar previous = 0;
  for (int x = 0; x < n; ++x) {
    if (regular[x]) {
      previous = a[x] + g[x] * previous;
      delta[x + 1] = previous;
      restricted[x] = 0;
    } else {
      previous = relaxed[x]
                     ? restricted_pressure_delta(level, v, k0 + x, r[x] + coupling * previous)
                     : Scalar(0);
      delta[x + 1] = 0;
      restricted[x] = previous;
    }
  }
  delta[n + 1] = 0;
  const Scalar two_inv_h2 = 2 * v.c.inv_h2;
  Scalar* __restrict p = v.p;
  // u_x[k + 1] += delta_k / h and u_x[k] -= delta_k / h, gathered per face.
  Scalar* __restrict ux = v.u[0];
#pragma omp simd
  for (int x = 0; x <= n; ++x) ux[k0 + x] += (delta[x] - delta[x + 1]) * v.c.inv_h;
  // p[k] += p_center delta_k and p[k +- 1] -= 2 delta_k / h^2, gathered per cell.
  p[k0 - 1] -= two_inv_h2 * delta[1];
#pragma omp simd
  for (int x = 0; x < n; ++x)
    p[k0 + x] += p_center * delta[x + 1] - two_inv_h2 * (delta[x] + delta[x + 2]);
  p[k0 + n] -= two_inv_h2 * delta[n];
  for (int i = 1; i < Dim; ++i) {
    const std::ptrdiff_t si = v.s[i];
    Scalar* __restrict ui = v.u[i];
#pragma omp simd
    for (int x = 0; x < n; ++x) {
      const Scalar du = delta[x + 1] * v.c.inv_h;
      ui[k0 + x + si] += du;
      ui[k0 + x] -= du;
    }
#pragma omp simd
    for (int x = 0; x < n; ++x) {
      p[k0 + x + si] -= two_inv_h2 * delta[x + 1];
      p[k0 + x - si] -= two_inv_h2 * delta[x + 1];
    }
  }
  for (int x = 0; x < n; ++x)
    if (restricted[x] != Scalar(0)) restricted_pressure_move(level, v, k0 + x, restricted[x]);
}

}  // namespace

template <int Dim, typename Scalar>
void distributive_sweep(Level<Dim, Scalar>& level) {
  const Views<Dim, Scalar> v(level);
  const MomentumRows<Dim, Scalar, 0> psi_x(level, v);
  const MomentumRows<Dim, Scalar, 1> psi_y(level, v);
  const MomentumRows<Dim, Scalar, Dim - 1> psi_z(level, v);
  const bool pressure = level.lambda > 0;
  auto q = [&](std::ptrdiff_t row, int length) {
    for (int first = 0; first < length; first += kRowChunk)
      relax_pressure_chunk(level, v, row + first, std::min(kRowChunk, length - first));
  };
  // Block by block: the block's four passes run while its fields are in cache.
  for (const auto& color : level.blocks.colors) {
    const auto count = static_cast<std::ptrdiff_t>(color.size());
#pragma omp parallel for schedule(dynamic, 1)
    for (std::ptrdiff_t b = 0; b < count; ++b) {
      const Block<Dim>& block = color[b];
      for_each_row_in_block(level.lattice, block, psi_x);
      for_each_row_in_block(level.lattice, block, psi_y);
      if constexpr (Dim == 3) for_each_row_in_block(level.lattice, block, psi_z);
      if (pressure) for_each_row_in_block(level.lattice, block, q);
    }
  }
}

template void distributive_sweep<2, float>(Level<2, float>&);
template void distributive_sweep<2, double>(Level<2, double>&);
template void distributive_sweep<3, float>(Level<3, float>&);
template void distributive_sweep<3, double>(Level<3, double>&);

}  // namespace mgelastic::grid
