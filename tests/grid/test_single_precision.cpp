// Single precision (MultigridOptions::mixed_precision = false): float levels hold the solution
// itself, as in the paper. The cycles are those of mixed precision until float round-off of the
// residual ends the reduction; the memory is about half.
#include <gtest/gtest.h>

#include <cmath>

#include "grid_test_support.hpp"
#include "mgelastic/core/error.hpp"
#include "mgelastic/grid/box_problem.hpp"
#include "mgelastic/grid/cycle_roofline.hpp"
#include "mgelastic/grid/multigrid.hpp"

namespace mgelastic::grid {
namespace {

MultigridOptions single_precision() {
  MultigridOptions options;
  options.mixed_precision = false;
  return options;
}

// Relative 2-norm of the difference of the two solvers' finest unknowns.
double solution_difference(const Multigrid<3, float>& a, const Multigrid<3, float>& b) {
  double difference = 0, norm = 0;
  for (int f = 0; f <= 3; ++f)
    for (std::size_t k = 0; k < a.finest().size(); ++k) {
      difference += std::pow(a.solution(f, k) - b.solution(f, k), 2);
      norm += std::pow(b.solution(f, k), 2);
    }
  return std::sqrt(difference / norm);
}

TEST(SinglePrecision, CyclesMatchMixedPrecisionAboveRoundOff) {
  Multigrid<3, float> mixed(test::mixed_box(32));
  Multigrid<3, float> single(test::mixed_box(32), single_precision());
  ASSERT_TRUE(single.single_precision());
  ASSERT_FALSE(mixed.single_precision());
  const std::vector<double> m = mixed.run_cycles(3).residuals;
  const std::vector<double> s = single.run_cycles(3).residuals;
  EXPECT_NEAR(s.front(), m.front(), 1e-6 * m.front());
  for (int c = 1; c <= 3; ++c)
    EXPECT_NEAR(s[c] / s.front(), m[c] / m.front(), 0.01 * m[c] / m.front());
  EXPECT_LT(s.back(), 0.02 * s.front());
}

TEST(SinglePrecision, ReachesThreeDigitsAndTheMixedSolution) {
  Multigrid<3, float> mixed(test::mixed_box(24));
  ASSERT_TRUE(mixed.solve(1e-9, 60).converged);
  Multigrid<3, float> single(test::mixed_box(24), single_precision());
  const SolveReport report = single.solve(1e-3, 30);
  EXPECT_TRUE(report.converged);
  // The displacements agree to ~2.5e-5 although the residual is only 1e-3 relative: float
  // round-off leaves high-frequency residuals that A^-1 damps.
  EXPECT_LT(solution_difference(single, mixed), 1e-4);
}

TEST(SinglePrecision, HalvesTheMemoryAndHasNoRefinement) {
  const Multigrid<3, float> mixed(test::mixed_box(32));
  const Multigrid<3, float> single(test::mixed_box(32), single_precision());
  EXPECT_LT(static_cast<double>(single.bytes()), 0.6 * static_cast<double>(mixed.bytes()));
  EXPECT_EQ(cycle_bytes(single).refinement, 0.0);
  EXPECT_GT(cycle_bytes(mixed).refinement, 0.0);
}

TEST(SinglePrecision, StateRoundTripsAndHasNoDoubleLevel) {
  Multigrid<3, float> single(test::mixed_box(16), single_precision());
  single.run_cycles(2);
  const double before = single.residual();
  const auto state = single.solution_state();
  single.run_cycles(1);
  // The cycles' norms come without a residual array on any level (fresh_residual_norm,
  // residual_restriction.hpp).
  for (int l = 0; l < single.levels(); ++l) EXPECT_TRUE(single.level(l).r[0].empty()) << l;
  single.set_solution_state(state);
  EXPECT_DOUBLE_EQ(single.residual(), before);  // float values survive the double copy exactly
  EXPECT_THROW(single.solution_level(), Error);
}

}  // namespace
}  // namespace mgelastic::grid
