#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "mgelastic/grid/box_problem.hpp"
#include "mgelastic/grid/coarsening.hpp"
#include "mgelastic/grid/level.hpp"
#include "mgelastic/grid/residual.hpp"
#include "mgelastic/grid/stencil.hpp"

namespace mgelastic::grid {
namespace {

// Level of a mixed box (fixed slab, traction faces: band rows next to the free faces) with
// random values in every entry of x and b, inactive and padding entries included (the
// vectorized residual evaluates every row and must still zero those without a stencil
// equation).
template <int Dim, typename Scalar>
Level<Dim, Scalar> random_mixed_level(int cells, double inertia, unsigned seed) {
  BoxSpec spec;
  spec.cells = cells;
  spec.poisson_ratio = 0.48;
  spec.boundary = BoxBoundary::MIXED;
  const auto problem = make_box_problem<Dim>(spec);
  const auto coarse_cells = coarsen_cells(problem.lattice, problem.cells);
  auto level = build_level<Dim, Scalar>(problem.lattice, problem.cells, problem.material, {},
                                        &coarse_cells, inertia);
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  for (int f = 0; f <= Dim; ++f) {
    for (std::size_t k = 0; k < level.size(); ++k) {
      level.x[f][k] = static_cast<Scalar>(1e-3 * normal(rng));
      level.b[f][k] = static_cast<Scalar>(normal(rng));
    }
  }
  return level;
}

// The point-wise stencil residual the vectorized one-pass kernel replaced: one row at a time,
// the select on the relaxation class before the stencil.
template <int Dim, typename Scalar, int Axis>
Scalar reference_momentum(const Level<Dim, Scalar>& level, std::ptrdiff_t k) {
  std::array<const Scalar*, Dim> u;
  std::array<std::ptrdiff_t, Dim> s;
  for (int i = 0; i < Dim; ++i) {
    u[i] = level.x[i].data();
    s[i] = level.lattice.stride(i);
  }
  const Scalar inv_h = static_cast<Scalar>(1.0 / level.lattice.h);
  const StencilConstants<Dim, Scalar> c{level.mu, inv_h, inv_h * inv_h};
  return level.b[Axis][k] - momentum_row<Dim, Scalar, Axis>(u, level.x[Dim].data(), s, k, c) +
         level.inertia * u[Axis][k];
}

template <int Dim, typename Scalar>
Scalar reference_pressure(const Level<Dim, Scalar>& level, std::ptrdiff_t k) {
  std::array<const Scalar*, Dim> u;
  std::array<std::ptrdiff_t, Dim> s;
  for (int i = 0; i < Dim; ++i) {
    u[i] = level.x[i].data();
    s[i] = level.lattice.stride(i);
  }
  const Scalar inv_h = static_cast<Scalar>(1.0 / level.lattice.h);
  const Scalar d = level.mu * level.mu / level.lambda;
  return level.b[Dim][k] - level.mu * divergence<Dim, Scalar>(u, s, k, inv_h) - d * level.x[Dim][k];
}

// Every stencil row of update_residual equals the point-wise residual to round-off, rows
// without an equation are exactly zero; in float and double, 2D and 3D, with the inertia term.
template <int Dim, typename Scalar>
void expect_residual_equals_pointwise(int cells, double inertia) {
  auto level = random_mixed_level<Dim, Scalar>(cells, inertia, 5);
  update_residual(level);
  const double tolerance = std::is_same_v<Scalar, float> ? 1e-5 : 1e-13;
  double scale = 0, difference = 0;
  std::size_t stencil_rows = 0, band_rows = 0;
  for (int f = 0; f <= Dim; ++f) {
    for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(level.size()); ++k) {
      const Relaxation relax = level.relaxation(f, k);
      if (relax == Relaxation::NONE) {
        ASSERT_EQ(level.r[f][k], Scalar(0)) << "field " << f << " at " << k;
        continue;
      }
      if (relax == Relaxation::BAND) {
        ++band_rows;
        continue;
      }
      Scalar expected;
      if (f == 0) expected = reference_momentum<Dim, Scalar, 0>(level, k);
      if (f == 1) expected = reference_momentum<Dim, Scalar, 1>(level, k);
      if constexpr (Dim == 3)
        if (f == 2) expected = reference_momentum<Dim, Scalar, 2>(level, k);
      if (f == Dim) expected = reference_pressure<Dim, Scalar>(level, k);
      scale = std::max(scale, std::abs(static_cast<double>(expected)));
      difference = std::max(difference, std::abs(static_cast<double>(level.r[f][k] - expected)));
      ++stencil_rows;
    }
  }
  EXPECT_GT(stencil_rows, level.size());  // most rows of all fields are stencil rows
  EXPECT_GT(band_rows, 0u);
  EXPECT_GT(scale, 1.0);
  EXPECT_LE(difference, tolerance * scale);
}

TEST(Residual, VectorizedStencilResidualEqualsPointwiseResidual) {
  expect_residual_equals_pointwise<3, double>(14, 0.0);
  expect_residual_equals_pointwise<3, float>(14, 0.0);
  expect_residual_equals_pointwise<3, double>(13, 2e5);
  expect_residual_equals_pointwise<2, double>(40, 0.0);
  expect_residual_equals_pointwise<2, float>(37, 2e5);
}

// The norm without a residual array: residual_into's bit for bit (the same sums in the same
// order), compute_residual's up to the order of the sum, and no r allocated.
TEST(Residual, FreshNormEqualsTheNormOfTheResidualArray) {
  auto level = random_mixed_level<3, double>(12, 0.0, 9);
  const double fresh = fresh_residual_norm(level);
  std::array<std::vector<double>, 4> r;
  std::array<double*, 4> out;
  for (int f = 0; f <= 3; ++f) {
    r[f].assign(level.size(), 0.0);
    out[f] = r[f].data();
  }
  EXPECT_EQ(fresh, (residual_into<3, double, double>(level, out)));
  auto single = random_mixed_level<2, float>(24, 0.0, 4);
  for (auto& field : single.r) field = FieldArray<float>();
  const double fresh_float = fresh_residual_norm(single);
  EXPECT_TRUE(single.r[0].empty());
  EXPECT_GT(fresh_float, 0.0);
  EXPECT_NEAR(fresh_float, compute_residual(single), 1e-12 * fresh_float);
}

}  // namespace
}  // namespace mgelastic::grid
