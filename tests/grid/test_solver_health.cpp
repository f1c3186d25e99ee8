#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "mgelastic/core/error.hpp"
#include "mgelastic/grid/box_problem.hpp"
#include "mgelastic/grid/multigrid.hpp"
#include "mgelastic/grid/solver_health.hpp"

namespace mgelastic::grid {
namespace {

// A 2D box with three levels (64, 32, 16 cells), so level 1 is smoothed, not solved directly.
MultigridOptions three_levels() {
  MultigridOptions options;
  options.coarsest_max_unknowns = 1000;
  options.coarsest_min_cells = 16;
  return options;
}

BoxSpec box_64() {
  BoxSpec spec;
  spec.cells = 64;
  return spec;
}

// The message of the Error `solve` throws.
template <typename Solve>
std::string failure(Solve&& solve) {
  try {
    solve();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "the solve did not throw";
  return "";
}

void expect_contains(const std::string& message, const std::string& part) {
  EXPECT_NE(message.find(part), std::string::npos) << "missing '" << part << "' in: " << message;
}

TEST(SolverHealth, HealthySolvesAreNotFlagged) {
  Multigrid<2, double> mg(make_box_problem<2>(box_64()), three_levels());
  ASSERT_EQ(mg.levels(), 3);
  const SolveReport report = mg.solve(1e-8, 30);
  EXPECT_TRUE(report.converged);
  EXPECT_EQ(divergence_reason(report.residuals), "");
}

TEST(SolverHealth, DivergenceReasonSeesNonFiniteAndGrowth) {
  EXPECT_EQ(divergence_reason({1.0, 0.5, 2e3}), "");
  EXPECT_NE(divergence_reason({1.0, 0.5, 2e4}).find("grew to 2.000e+04"), std::string::npos);
  EXPECT_EQ(divergence_reason({1.0, std::nan("")}), "the residual is not finite");
  EXPECT_EQ(divergence_reason({1.0, std::numeric_limits<double>::infinity()}),
            "the residual is not finite");
}

// Progress is measured from the first cycle on: a residual history shaped like the armadillo's
// at 128 cells in single precision (x14 in the first cycle, then 0.56 per cycle) does not stall,
// while the same history wandering at a floor does, after three cycles without a new minimum.
TEST(SolverHealth, StallWatchIgnoresTheFirstCyclesGrowth) {
  StallWatch converging(3);
  double r = 14.0;
  for (int cycle = 0; cycle < 20; ++cycle, r *= 0.56) EXPECT_FALSE(converging.stalled_after(r));
  StallWatch floor(3);
  for (double residual : {14.0, 1.0, 0.1, 0.01}) EXPECT_FALSE(floor.stalled_after(residual));
  EXPECT_FALSE(floor.stalled_after(0.012));
  EXPECT_FALSE(floor.stalled_after(0.011));
  EXPECT_TRUE(floor.stalled_after(0.013));
  StallWatch off(0);
  for (int cycle = 0; cycle < 5; ++cycle) EXPECT_FALSE(off.stalled_after(1.0));
}

// NaN in level 1's interior operator: the replay pins the first non-finite residual on level 1,
// right where the restricted residual arrives, not on the finest level where it surfaces.
TEST(SolverHealth, NanInACoarseLevelIsLocated) {
  for (bool accelerated : {false, true}) {
    Multigrid<2, double> mg(make_box_problem<2>(box_64()), three_levels());
    mg.level(1).mu = std::numeric_limits<double>::quiet_NaN();
    const std::string message =
        failure([&] { accelerated ? mg.solve_accelerated(1e-8, 30) : mg.solve(1e-8, 30); });
    expect_contains(message, accelerated ? "accelerated solve (FGMRES)" : "V-cycle 1 diverged");
    expect_contains(message, "residual is not finite");
    expect_contains(message, "residual history: ");
    expect_contains(message, "cycle 1, level 1 of 3 (0 = finest), restriction");
    expect_contains(message, "residual is not finite while its unknowns are");
  }
}

// A broken smoother, not a broken operator: a NaN in one inverted band block of level 1 (used only
// by the boundary band Gauss-Seidel) writes NaN into level 1's unknowns during its first
// pre-smoothing, and the replay names exactly that phase.
TEST(SolverHealth, NanProducedByTheBoundarySmootherIsNamed) {
  Multigrid<2, double> mg(make_box_problem<2>(box_64()), three_levels());
  ASSERT_FALSE(mg.level(1).band_block_inverse.empty());
  mg.level(1).band_block_inverse[0] = std::numeric_limits<double>::quiet_NaN();
  const std::string message = failure([&] { mg.solve(1e-8, 30); });
  expect_contains(message, "V-cycle 1 diverged: the residual is not finite");
  expect_contains(message,
                  "cycle 1, level 1 of 3 (0 = finest), pre-smoothing (boundary band sweeps) first "
                  "produced non-finite values");
}

// A coarse level whose operator is 1000 times too soft returns a correction 1000 times too large:
// the residual grows every cycle, and the replay finds the prolongation into level 0 (where the
// oversized correction lands) as the phase that grows the residual most.
TEST(SolverHealth, ResidualGrowthIsTracedToItsPhase) {
  Multigrid<2, double> mg(make_box_problem<2>(box_64()), three_levels());
  mg.level(1).mu *= 1e-3;
  mg.level(1).lambda *= 1e-3;
  const std::string message = failure([&] { mg.solve(1e-8, 50); });
  expect_contains(message, "diverged: the residual grew to");
  expect_contains(message, "grew its level's residual the most");
  expect_contains(message, "prolongation");
}

// The last residual of a solve's history as its message prints it.
double last_in_history(const std::string& message) {
  const std::string key = "residual history: ";
  const std::size_t begin = message.find(key) + key.size();
  const std::size_t end = message.find(';', begin);
  const std::string history = message.substr(begin, end - begin);
  return std::stod(history.substr(history.rfind(' ') + 1));
}

// Mixed precision keeps a solve's start for the replay as the live chunks of x, or nothing when x
// starts at zero: either way the replay ends where the solve did (a wrong start would not).
TEST(SolverHealth, ReplayRestartsFromTheSolvesStart) {
  for (int earlier_cycles : {0, 3}) {
    Multigrid<2, float> mg(make_box_problem<2>(box_64()), three_levels());
    ASSERT_FALSE(mg.single_precision());  // a double solution level over float levels
    mg.run_cycles(earlier_cycles);
    mg.level(1).mu *= 1e-3;
    mg.level(1).lambda *= 1e-3;
    const std::string message = failure([&] { mg.solve(1e-8, 50); });
    expect_contains(message, "diverged: the residual grew to");
    const double last = last_in_history(message);
    EXPECT_NEAR(mg.residual(), last, 1e-3 * last) << earlier_cycles;
  }
}

}  // namespace
}  // namespace mgelastic::grid
