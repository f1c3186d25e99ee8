// solver.precision "single" in a grid simulation (float cycles on a float solution, no double
// solution level): it converges to float round-off, agrees with the mixed-precision ("float")
// solve to within what float arithmetic allows, stops where the residual stalls instead of
// spending the cycle limit, and holds less solver memory than the mixed run.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "mgelastic/sim/simulation.hpp"
#include "sim/sim_test_support.hpp"

namespace mgelastic::sim {
namespace {

constexpr int kCells = 12;  // grid.resolution: cells along the cube's side

// A 0.2 m cube standing on a fixed floor layer under gravity: a compact body, so the float
// round-off of its operator is governed by the mesh ((L/h)^2), not by slender bending.
nlohmann::json cube(const std::string& precision, double tolerance) {
  nlohmann::json s = nlohmann::json::parse(R"({
    "engine": "grid",
    "geometry": {"box": {"size": [0.2, 0.2, 0.2]}},
    "material": {"youngs_modulus": 1e5, "poisson_ratio": 0.3, "density": 1000},
    "constraints": [
      {"region": {"box": {"center": [0, -0.1, 0], "size": [0.4, 0.04, 0.4]}}, "motion": "fixed"}],
    "loads": {"gravity": [0, -9.81, 0]},
    "solver": {"max_vcycles": 60},
    "output": {"formats": ["obj"]}})");
  s["grid"] = {{"resolution", kCells}};
  s["solver"]["precision"] = precision;
  s["solver"]["tolerance"] = tolerance;
  return s;
}

using test::make;

// Relative round-off of a float solve of a second-order operator on n cells: float's epsilon
// times the operator's condition growth (L/h)^2 (1.7e-5 at 12 cells; measured on this cube:
// displacement 1.7e-6 from the mixed solve, stalled residual 4.7e-6).
double float_roundoff(int n) {
  return std::numeric_limits<float>::epsilon() * n * n;
}

double max_abs(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

TEST(SinglePrecision, QuasistaticSolveReducesTheResidualToFloatRoundOff) {
  Simulation s(make(cube("single", 1e-3)));
  const FrameStats& stats = s.step();
  ASSERT_TRUE(s.grid()->single_precision());
  EXPECT_TRUE(stats.converged);
  EXPECT_LE(stats.worst_residual, 1e-3);
  EXPECT_GT(stats.cycles, 1);
}

TEST(SinglePrecision, DisplacementAgreesWithMixedPrecisionToFloatRoundOff) {
  Simulation single(make(cube("single", 1e-12)));
  Simulation mixed(make(cube("float", 1e-10)));
  single.step();
  ASSERT_TRUE(mixed.step().converged);
  const std::vector<double>& a = single.grid()->displacement().values;
  const std::vector<double>& b = mixed.grid()->displacement().values;
  ASSERT_EQ(a.size(), b.size());
  std::vector<double> difference(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) difference[i] = a[i] - b[i];
  const double scale = max_abs(b);
  ASSERT_GT(scale, 0.0);
  const double relative = max_abs(difference) / scale;
  EXPECT_LT(relative, float_roundoff(kCells)) << "relative difference " << relative;
  // Not the same arithmetic: the single run is a float solve, not a copy of the mixed one.
  EXPECT_GT(relative, 0.0);
}

// A tolerance below float round-off: the solve stops once three cycles bring no new smallest
// residual, reports that it did not converge and why, and does not spend the cycle limit.
TEST(SinglePrecision, UnreachableToleranceStopsWhereTheResidualStalls) {
  const nlohmann::json document = cube("single", 1e-12);
  Simulation s(make(document));
  const FrameStats& stats = s.step();
  ASSERT_EQ(stats.step_stats.size(), 1u);
  const StepStats& step = stats.step_stats.front();
  EXPECT_FALSE(step.converged);
  EXPECT_TRUE(step.stalled);
  EXPECT_LT(step.cycles, document["solver"]["max_vcycles"].get<int>());
  // It stalled at round-off, not early: the residual fell well below the first cycles' level.
  EXPECT_LT(step.relative_residual, float_roundoff(kCells));
}

// Plain cycles in mixed and double precision stop the same way at double's round-off floor (the
// residual of x's own rounding, ~1e-14 relative on this small cube), instead of running every
// cycle up to max_vcycles; a reachable tolerance converges without a stall.
TEST(SinglePrecision, PlainCyclesStopAtDoublesRoundOffFloorToo) {
  for (const std::string precision : {"float", "double"}) {
    nlohmann::json document = cube(precision, 1e-30);
    document["solver"]["accelerate"] = false;
    document["solver"]["max_vcycles"] = 200;
    Simulation s(make(document));
    const StepStats& step = s.step().step_stats.front();
    EXPECT_FALSE(step.converged) << precision;
    EXPECT_TRUE(step.stalled) << precision;
    EXPECT_LT(step.cycles, 60) << precision;
    EXPECT_LT(step.relative_residual, 1e-11) << precision;  // far below float round-off
    document["solver"]["tolerance"] = 1e-10;
    const StepStats reachable = Simulation(make(document)).step().step_stats.front();
    EXPECT_TRUE(reachable.converged) << precision;
    EXPECT_FALSE(reachable.stalled) << precision;
  }
}

TEST(SinglePrecision, MixedPrecisionReachesTheSameToleranceWithoutStalling) {
  const FrameStats stats = Simulation(make(cube("float", 1e-9))).step();
  EXPECT_TRUE(stats.converged);
  EXPECT_FALSE(stats.step_stats.front().stalled);
}

// The mixed run keeps a double copy of the finest level beside the float hierarchy; single
// precision does not: at least that copy's x and b (4 unknowns per padded lattice point, 8
// bytes each) are saved.
TEST(SinglePrecision, SolverHoldsLessMemoryThanMixedPrecision) {
  Simulation single(make(cube("single", 1e-3)));
  Simulation mixed(make(cube("float", 1e-3)));
  const Eigen::Vector3i n = single.grid()->cells();
  const double padded = (n.array() + 2).cast<double>().prod();
  const double double_x_and_b = 2 * 4 * padded * sizeof(double);
  const double saved =
      static_cast<double>(mixed.grid()->bytes()) - static_cast<double>(single.grid()->bytes());
  EXPECT_GE(saved, double_x_and_b)
      << "single " << single.grid()->bytes() << " B, mixed " << mixed.grid()->bytes() << " B";
}

// Reactions need the double solution level's rows: none in single precision, and the run says
// so (constraint_reactions returns nothing) instead of failing.
TEST(SinglePrecision, HasNoDoubleSolutionLevelForReactions) {
  Simulation s(make(cube("single", 1e-3)));
  s.step();
  EXPECT_EQ(s.grid()->linear_solution(), nullptr);
}

}  // namespace
}  // namespace mgelastic::sim
