#include <gtest/gtest.h>

#include <random>

#include "grid_test_support.hpp"
#include "mgelastic/core/threads.hpp"
#include "mgelastic/grid/box_problem.hpp"
#include "mgelastic/grid/distributive_smoother.hpp"
#include "mgelastic/grid/level.hpp"
#include "mgelastic/grid/residual.hpp"
#include "mgelastic/grid/stencil.hpp"

namespace mgelastic::grid {
namespace {

// Level of a Dirichlet-walled box with random unknowns and right-hand side.
template <typename Scalar = double>
Level<3, Scalar> random_level(double poisson, unsigned seed, double inertia = 0.0, int cells = 12) {
  BoxSpec spec;
  spec.cells = cells;
  spec.poisson_ratio = poisson;
  spec.boundary = BoxBoundary::DIRICHLET;
  const auto problem = make_box_problem<3>(spec);
  auto level = build_level<3, Scalar>(problem.lattice, problem.cells, problem.material, {}, nullptr,
                                      inertia);
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  for (int f = 0; f <= 3; ++f) {
    for (std::size_t k = 0; k < level.size(); ++k) {
      if (level.kind(f, k) != VarKind::INTERIOR) continue;
      level.x[f][k] = static_cast<Scalar>(1e-3 * normal(rng));
      level.b[f][k] = static_cast<Scalar>(normal(rng));
    }
  }
  return level;
}

// The composed operator L M is lower triangular with Laplacian diagonal blocks (Eq. 7): a full
// interior distributive sweep of the (uniform) interior equations drives the residual of
// smooth-free random data down like Gauss-Seidel on a Laplacian, for any Poisson ratio, and
// never increases the interior residual.
class DistributiveSweep : public ::testing::TestWithParam<double> {};

TEST_P(DistributiveSweep, ReducesInteriorResidualIndependentlyOfPoissonRatio) {
  auto level = random_level(GetParam(), 5);
  auto interior_norm = [&] {
    compute_residual(level);
    double sum = 0;
    for (int f = 0; f <= 3; ++f)
      for (std::size_t k = 0; k < level.size(); ++k)
        if (level.relaxation(f, k) == Relaxation::DISTRIBUTIVE)
          sum += level.r[f][k] * level.r[f][k];
    return std::sqrt(sum);
  };
  const double before = interior_norm();
  for (int sweep = 0; sweep < 3; ++sweep) distributive_sweep(level);
  const double after = interior_norm();
  // Three lexicographic Gauss-Seidel sweeps on a Laplacian reduce random residuals by far more
  // than 2x; a wrong (LM)_ii or distribution would stall or diverge at nu -> 0.5.
  EXPECT_LT(after, 0.5 * before) << "nu = " << GetParam();
}

INSTANTIATE_TEST_SUITE_P(PoissonRatios, DistributiveSweep,
                         ::testing::Values(0.0, 0.2, 0.3, 0.45, 0.49, 0.4999));

// A q step zeroes its own pressure equation: the last cell the sweep relaxes keeps a zero
// residual because nothing moves afterwards.
TEST(DistributiveSweep, PressureStepZeroesPressureResidualOfTheLastCell) {
  auto level = random_level(0.45, 9);
  distributive_sweep(level);
  compute_residual(level);
  // The last distributive pressure visited (last block of the last color, p after the momentum
  // passes) is relaxed after everything else in the sweep.
  std::ptrdiff_t last = -1;
  for (const auto& color : level.blocks.colors)
    for (const auto& block : color)
      for_each_in_block(level.lattice, block, [&](std::ptrdiff_t k) {
        if (level.relaxation(3, k) == Relaxation::DISTRIBUTIVE) last = k;
      });
  ASSERT_GE(last, 0);
  EXPECT_NEAR(level.r[3][last], 0.0, 1e-9 * std::abs(level.b[3][last]) + 1e-12);
}

// Algorithm 2 point by point, in the colored blocks' lexicographic order: the definition the
// row-wise kernel (residuals of a row segment first, then the delta recurrence) must reproduce.
void reference_sweep(Level<3, double>& level) {
  std::array<double*, 3> u{};
  std::array<const double*, 3> uc{};
  std::array<std::ptrdiff_t, 3> s{};
  for (int i = 0; i < 3; ++i) {
    u[i] = level.x[i].data();
    uc[i] = u[i];
    s[i] = level.lattice.stride(i);
  }
  double* p = level.x[3].data();
  const double mu = level.mu, lambda = level.lambda, c = level.inertia;
  const double inv_h = 1.0 / level.lattice.h, inv_h2 = inv_h * inv_h;
  const StencilConstants<3, double> sc{mu, inv_h, inv_h2};
  auto momentum = [&]<int Axis>(std::ptrdiff_t k) {
    if (level.relaxation(Axis, k) != Relaxation::DISTRIBUTIVE) return;
    const double r =
        level.b[Axis][k] - momentum_row<3, double, Axis>(uc, p, s, k, sc) + c * u[Axis][k];
    const double delta = -r / (6 * mu * inv_h2 + c);
    u[Axis][k] += delta;
    p[k] -= delta * inv_h;
    p[k - s[Axis]] += delta * inv_h;
  };
  auto pressure = [&](std::ptrdiff_t k) {
    if (level.relaxation(3, k) != Relaxation::DISTRIBUTIVE) return;
    const double r =
        lambda * (level.b[3][k] - mu * divergence<3, double>(uc, s, k, inv_h)) - mu * mu * p[k];
    auto interior = [&](std::ptrdiff_t j) { return level.cells[j] == CellType::INTERIOR; };
    int moved = 0;
    for (int i = 0; i < 3; ++i) moved += interior(k - s[i]) + interior(k + s[i]);
    const double delta = r / ((lambda * mu * moved + 12 * mu * mu) * inv_h2 + mu * c);
    for (int i = 0; i < 3; ++i) {
      if (interior(k + s[i])) {
        u[i][k + s[i]] += delta * inv_h;
        p[k + s[i]] -= 2 * delta * inv_h2;
      }
      if (interior(k - s[i])) {
        u[i][k] -= delta * inv_h;
        p[k - s[i]] -= 2 * delta * inv_h2;
      }
    }
    p[k] += (12 * inv_h2 + c / mu) * delta;
  };
  // Block by block (colors in turn), in each block u_1, u_2, u_3, then p.
  for (const auto& color : level.blocks.colors) {
    for (const auto& block : color) {
      for_each_in_block(level.lattice, block,
                        [&](std::ptrdiff_t k) { momentum.template operator()<0>(k); });
      for_each_in_block(level.lattice, block,
                        [&](std::ptrdiff_t k) { momentum.template operator()<1>(k); });
      for_each_in_block(level.lattice, block,
                        [&](std::ptrdiff_t k) { momentum.template operator()<2>(k); });
      for_each_in_block(level.lattice, block, pressure);
    }
  }
}

// The kernel relaxes an x-row segment in passes (all residuals, the scalar delta recurrence,
// all distributions); it must give the point-by-point sweep's values up to round-off, next to
// Dirichlet walls (restricted q steps) and with the inertia term of a dynamics step.
TEST(DistributiveSweep, RowWiseKernelEqualsPointByPointSweep) {
  for (const double inertia : {0.0, 3e7}) {
    auto level = random_level(0.45, 11, inertia);
    auto reference = level;
    distributive_sweep(level);
    reference_sweep(reference);
    double scale = 0, difference = 0, moved = 0;
    const auto start = random_level(0.45, 11, inertia);
    for (int f = 0; f <= 3; ++f) {
      for (std::size_t k = 0; k < level.size(); ++k) {
        scale = std::max(scale, std::abs(reference.x[f][k]));
        difference = std::max(difference, std::abs(level.x[f][k] - reference.x[f][k]));
        moved = std::max(moved, std::abs(reference.x[f][k] - start.x[f][k]));
      }
    }
    EXPECT_GT(moved, 0.1 * scale) << "the sweep must move the unknowns";
    EXPECT_LE(difference, 1e-12 * scale) << "inertia " << inertia;
  }
}

// Blocks of one color run concurrently, each relaxed by one thread with its own row-chunk
// recurrences: the values must not depend on which thread gets which block (bit for bit, float
// and double, with several blocks per color on 40^3).
template <typename Scalar>
void expect_sweep_independent_of_thread_count() {
  auto serial = random_level<Scalar>(0.48, 13, 0.0, 40);
  auto parallel = serial;
  ASSERT_GT(serial.blocks.colors[0].size(), 1u);
  set_thread_count(1);
  for (int sweep = 0; sweep < 2; ++sweep) distributive_sweep(serial);
  set_thread_count(2);
  for (int sweep = 0; sweep < 2; ++sweep) distributive_sweep(parallel);
  set_thread_count(0);
  for (int f = 0; f <= 3; ++f)
    for (std::size_t k = 0; k < serial.size(); ++k)
      ASSERT_EQ(serial.x[f][k], parallel.x[f][k]) << "field " << f << " index " << k;
}

TEST(DistributiveSweep, DoesNotDependOnThreadCountInFloat) {
  expect_sweep_independent_of_thread_count<float>();
}

TEST(DistributiveSweep, DoesNotDependOnThreadCountInDouble) {
  expect_sweep_independent_of_thread_count<double>();
}

}  // namespace
}  // namespace mgelastic::grid
