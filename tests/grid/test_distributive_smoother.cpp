#include <gtest/gtest.h>

#include <random>

#include "grid_test_support.hpp"
#include "mgelastic/grid/box_problem.hpp"
#include "mgelastic/grid/distributive_smoother.hpp"
#include "mgelastic/grid/level.hpp"
#include "mgelastic/grid/residual.hpp"

namespace mgelastic::grid {
namespace {

// Level of a Dirichlet-walled box with random unknowns and right-hand side.
Level<3, double> random_level(double poisson, unsigned seed) {
  BoxSpec spec;
  spec.cells = 12;
  spec.poisson_ratio = poisson;
  spec.boundary = BoxBoundary::DIRICHLET;
  const auto problem = make_box_problem<3>(spec);
  auto level =
      build_level<3, double>(problem.lattice, problem.cells, problem.material, {}, nullptr);
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  for (int f = 0; f <= 3; ++f) {
    for (std::size_t k = 0; k < level.size(); ++k) {
      if (level.kind[f][k] != VarKind::INTERIOR) continue;
      level.x[f][k] = 1e-3 * normal(rng);
      level.b[f][k] = normal(rng);
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
        if (level.relaxation[f][k] == Relaxation::DISTRIBUTIVE)
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
  // The last distributive pressure visited is relaxed after everything else in the sweep.
  std::size_t last = 0;
  for (std::size_t k = 0; k < level.size(); ++k)
    if (level.relaxation[3][k] == Relaxation::DISTRIBUTIVE) last = k;
  EXPECT_NEAR(level.r[3][last], 0.0, 1e-9 * std::abs(level.b[3][last]) + 1e-12);
}

}  // namespace
}  // namespace mgelastic::grid
