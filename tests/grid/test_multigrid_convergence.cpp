#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "grid_test_support.hpp"
#include "mgelastic/grid/box_problem.hpp"
#include "mgelastic/grid/convergence_rate.hpp"
#include "mgelastic/grid/multigrid.hpp"

namespace mgelastic::grid {
namespace {

template <int Dim, typename Scalar>
double box_rate(int n, double poisson, CycleType cycle = CycleType::V, int cycles = 12) {
  BoxSpec spec;
  spec.cells = n;
  spec.poisson_ratio = poisson;
  MultigridOptions options;
  options.cycle = cycle;
  Multigrid<Dim, Scalar> mg(make_box_problem<Dim>(spec), options);
  return convergence_rate(mg.run_cycles(cycles).residuals);
}

struct RateAndLevels {
  double rate;
  int levels;
};

template <int Dim>
RateAndLevels mixed_box_rate(int n, bool consistent_dirichlet_depth = true,
                             bool misaligned_dirichlet_depth = true) {
  BoxSpec spec;
  spec.cells = n;
  spec.poisson_ratio = 0.49;
  MultigridOptions options;
  options.consistent_dirichlet_depth = consistent_dirichlet_depth;
  options.misaligned_dirichlet_depth = misaligned_dirichlet_depth;
  Multigrid<Dim, double> mg(make_box_problem<Dim>(spec), options);
  return {convergence_rate(mg.run_cycles(12).residuals), mg.levels()};
}

// The block-local band order (MultigridOptions::band_sweep_order) keeps the V(1,1) rate of the
// paper's band-wide order within 0.03 (issue 24's acceptance) on the mixed box at nu 0.495 (the
// most band sweeps) and on an embedded ball with a clamped cap (band rows of every shape).
double rate_with_order(const ElasticityProblem<3>& problem, BandSweepOrder order) {
  MultigridOptions options;
  options.band_sweep_order = order;
  Multigrid<3, float> mg(problem, options);
  return convergence_rate(mg.run_cycles(12).residuals);
}

TEST(MultigridSolve, BlockLocalBandOrderKeepsTheRate) {
  BoxSpec spec;
  spec.cells = 32;
  spec.poisson_ratio = 0.495;
  const std::vector<std::pair<std::string, ElasticityProblem<3>>> cases = {
      {"box 32^3 nu 0.495", make_box_problem<3>(spec)},
      {"clamped ball 32^3", test::clamped_ball(32)}};
  for (const auto& [name, problem] : cases) {
    const double local = rate_with_order(problem, BandSweepOrder::BLOCK_LOCAL);
    const double wide = rate_with_order(problem, BandSweepOrder::BAND_WIDE);
    std::printf("%s: V(1,1) rate block-local %.4f, band-wide %.4f\n", name.c_str(), local, wide);
    EXPECT_LE(local, wide + 0.03) << name;
    EXPECT_LT(local, 0.9) << name;
  }
}

// Acceptance (issue 2): residual reduction per V(1,1) cycle <= 0.35 on the mixed box for Poisson
// ratios up to 0.495, in 3D and 2D (paper: 0.26-0.28).
class MixedBoxRate : public ::testing::TestWithParam<double> {};

TEST_P(MixedBoxRate, ThreeDimensionalN32) {
  EXPECT_LE((box_rate<3, double>(32, GetParam())), 0.35);
}

// N = 64 in single precision (mixed-precision cycles) keeps the test fast on two cores.
TEST_P(MixedBoxRate, ThreeDimensionalN64) {
  EXPECT_LE((box_rate<3, float>(64, GetParam())), 0.35);
}

TEST_P(MixedBoxRate, TwoDimensionalResolutionIndependent) {
  const double coarse = box_rate<2, double>(32, GetParam());
  const double fine = box_rate<2, double>(64, GetParam());
  EXPECT_LE(coarse, 0.35);
  EXPECT_LE(fine, 0.35);
  EXPECT_LE(fine, coarse + 0.05);
}

INSTANTIATE_TEST_SUITE_P(PoissonRatios, MixedBoxRate,
                         ::testing::Values(0.2, 0.3, 0.45, 0.49, 0.495));

// Each added level keeps the V(1,1) rate (+0.05): 64^2 to 512^2 build 2 to 5 levels. Before
// coarse levels clamped tangential corrections at the finest level's Dirichlet depth, each level
// beyond the third cost ~0.11 (256^2 with 2 / 3 / 4 levels: 0.21 / 0.23 / 0.35;
// docs/grid-engine.md, decision 8a).
TEST(MultigridSolve, MixedBoxRateIsDepthIndependentIn2D) {
  const RateAndLevels shallow = mixed_box_rate<2>(64);
  EXPECT_EQ(shallow.levels, 2);
  EXPECT_LE(shallow.rate, 0.3);
  int levels = shallow.levels;
  for (int n : {128, 256, 512}) {
    const RateAndLevels deep = mixed_box_rate<2>(n);
    EXPECT_EQ(deep.levels, ++levels) << n;
    EXPECT_LE(deep.rate, shallow.rate + 0.05) << n << "^2, " << deep.levels << " levels";
  }
}

// The cause of the loss: a coarse level's tangential Dirichlet variable sits H/2 inside the
// clamp, so with the paper's rediscretization the coarse clamp recedes with depth and the coarse
// correction of the bending mode is too weak (the residual collects in the tangential momentum
// rows next to the clamp).
TEST(MultigridSolve, RecedingCoarseClampSlowsDeepHierarchies) {
  const RateAndLevels consistent = mixed_box_rate<2>(256);
  const RateAndLevels receding = mixed_box_rate<2>(256, false);
  EXPECT_EQ(receding.levels, 4);
  EXPECT_GE(receding.rate, consistent.rate + 0.08);
}

// Decision 8a on a misaligned clamp: the slab of the mixed box is n/8 finest rows thick, at 24^3
// 3 rows, so the coarse Dirichlet cells' wall stands one finest row above the finest one; at
// 80^2 10 rows, two above it on the third level. Clamping the coarse tangential corrections at
// the finest wall (misaligned_dirichlet_depth; finest_dirichlet_wall_layers counts the layers)
// instead of the coarse wall brings the rate toward the aligned boxes' (3D 48^3, nu 0.48: 0.23).
// Measured: 3D 24^3 float nu 0.48 0.328 instead of 0.399; 2D 80^2 nu 0.49 0.284 instead of 0.321.
TEST(MultigridSolve, MisalignedClampIsClampedAtTheFinestDepth) {
  const auto rate3 = [](bool misaligned) {
    BoxSpec spec;
    spec.cells = 24;
    spec.poisson_ratio = 0.48;
    Multigrid<3, float> mg(make_box_problem<3>(spec), {.misaligned_dirichlet_depth = misaligned});
    EXPECT_EQ(mg.levels(), 2);
    return convergence_rate(mg.run_cycles(12).residuals);
  };
  const double finest3 = rate3(true), coarse_wall3 = rate3(false);
  EXPECT_LE(finest3, 0.36);
  EXPECT_LE(finest3, coarse_wall3 - 0.04);
  const RateAndLevels finest2 = mixed_box_rate<2>(80);
  const RateAndLevels coarse_wall2 = mixed_box_rate<2>(80, true, false);
  EXPECT_EQ(finest2.levels, 3);
  EXPECT_LE(finest2.rate, coarse_wall2.rate - 0.02);
}

// 3D: 16^3 and 32^3 (2 levels) to 64^3 (3 levels) within +0.05.
TEST(MultigridSolve, MixedBoxRateIsResolutionIndependentIn3D) {
  const RateAndLevels coarse = mixed_box_rate<3>(16);
  EXPECT_LE(coarse.rate, 0.3);
  for (int n : {32, 64}) {
    const RateAndLevels fine = mixed_box_rate<3>(n);
    EXPECT_LE(fine.rate, coarse.rate + 0.05) << n << "^3, " << fine.levels << " levels";
  }
}

// With W(1,1) cycles the 3D rate is independent of the resolution (+0.05 from 32^3 to 64^3).
TEST(MultigridSolve, WCycleRateIsResolutionIndependentIn3D) {
  const double coarse = box_rate<3, float>(32, 0.3, CycleType::W);
  const double fine = box_rate<3, float>(64, 0.3, CycleType::W);
  EXPECT_LE(fine, coarse + 0.05);
  EXPECT_LE(fine, 0.3);
}

// Double precision reaches a relative residual of 1e-10; single precision (float V-cycles with
// a double residual) reaches 1e-5 and beyond.
TEST(MultigridSolve, DoubleReachesTenDigits) {
  BoxSpec spec;
  spec.cells = 16;
  spec.poisson_ratio = 0.49;
  Multigrid<3, double> mg(make_box_problem<3>(spec));
  const SolveReport report = mg.solve(1e-10, 40);
  EXPECT_TRUE(report.converged);
  EXPECT_LE(report.residuals.back(), 1e-10 * report.residuals.front());
}

TEST(MultigridSolve, FloatReachesFiveDigits) {
  BoxSpec spec;
  spec.cells = 16;
  spec.poisson_ratio = 0.49;
  Multigrid<3, float> mg(make_box_problem<3>(spec));
  const SolveReport report = mg.solve(1e-5, 40);
  EXPECT_TRUE(report.converged);
  EXPECT_LE(report.residuals.back(), 1e-5 * report.residuals.front());
}

TEST(MultigridSolve, DirichletBoxConvergesAtModeratePoissonRatio) {
  BoxSpec spec;
  spec.cells = 24;
  spec.poisson_ratio = 0.3;
  spec.boundary = BoxBoundary::DIRICHLET;
  Multigrid<3, double> mg(make_box_problem<3>(spec));
  EXPECT_LE(convergence_rate(mg.run_cycles(12).residuals), 0.45);
}

// solve()'s stall_cycles stops only a residual that no longer sets new minima: a converging
// double solve runs exactly as without it.
TEST(MultigridSolve, StallStopLeavesAConvergingSolveAlone) {
  BoxSpec spec;
  spec.cells = 32;
  spec.poisson_ratio = 0.45;
  Multigrid<2, double> plain(make_box_problem<2>(spec)), watched(make_box_problem<2>(spec));
  const SolveReport a = plain.solve(1e-10, 60);
  const SolveReport b = watched.solve(1e-10, 60, 3);
  EXPECT_TRUE(b.converged);
  EXPECT_FALSE(b.stalled);
  EXPECT_EQ(a.residuals, b.residuals);
}

// Single precision (no double solution level) cannot reach 1e-14: the solve stops once three
// cycles bring no new smallest residual, well before the cycle limit, and says why.
TEST(MultigridSolve, SinglePrecisionStopsWhereRoundOffStallsTheResidual) {
  BoxSpec spec;
  spec.cells = 32;
  spec.poisson_ratio = 0.45;
  MultigridOptions options;
  options.mixed_precision = false;
  Multigrid<2, float> mg(make_box_problem<2>(spec), options);
  const SolveReport r = mg.solve(1e-14, 100, 3);
  EXPECT_FALSE(r.converged);
  EXPECT_TRUE(r.stalled);
  EXPECT_LT(r.cycles(), 100);
  EXPECT_LT(r.residuals.back(), 1e-3 * r.residuals.front());  // it converged first
}

// The accelerated solve in double cannot reach 1e-18 either (the residual of x's own rounding,
// ~eps |A| |x|, is far above eps |b|): it stops at that floor, well before the cycle limit, and
// says why, after the residual had fallen as far as it can. A reachable tolerance on the same
// problem converges without a stall.
TEST(MultigridSolve, AcceleratedSolveStopsAtTheRoundOffFloor) {
  const BoxSpec spec{.cells = 16, .poisson_ratio = 0.45};
  Multigrid<3, double> mg(make_box_problem<3>(spec));
  const SolveReport r = mg.solve_accelerated(1e-18, 200);
  EXPECT_FALSE(r.converged);
  EXPECT_TRUE(r.stalled);
  EXPECT_LT(r.cycles(), 80);
  EXPECT_LT(r.residuals.back(), 1e-12 * r.residuals.front());
  Multigrid<3, double> reachable(make_box_problem<3>(spec));
  const SolveReport ok = reachable.solve_accelerated(1e-10, 200);
  EXPECT_TRUE(ok.converged);
  EXPECT_FALSE(ok.stalled);
}

TEST(ConvergenceRate, GeometricMeanOfLastFiveRatiosAboveFloor) {
  const std::vector<double> residuals{1.0, 0.5, 0.1, 0.01, 1e-3, 1e-4, 1e-5, 1e-6, 1e-12, 1e-13};
  // Cycles 8 and 9 are below 1e-11 of the initial residual and do not count.
  EXPECT_NEAR(convergence_rate(residuals), 0.1, 1e-12);
  EXPECT_NEAR(last_ratio(residuals), 0.1, 1e-12);  // cycle 7, the last above the floor
  EXPECT_TRUE(rate_settled(residuals));
}

TEST(ConvergenceRate, ClimbingRatiosAreNotSettled) {
  // The armadillo-at-256 pattern: a fast start, then a slow mode takes over.
  std::vector<double> residuals{1.0};
  for (double ratio : {0.35, 0.35, 0.35, 0.40, 0.49, 0.63, 0.73, 0.76})
    residuals.push_back(residuals.back() * ratio);
  EXPECT_FALSE(rate_settled(residuals));  // 0.63, 0.73, 0.76
  EXPECT_NEAR(last_ratio(residuals), 0.76, 1e-12);
  residuals.push_back(residuals.back() * 0.77);
  EXPECT_FALSE(rate_settled(residuals));  // 0.73 .. 0.77: 0.04 apart
  residuals.push_back(residuals.back() * 0.775);
  residuals.push_back(residuals.back() * 0.776);
  EXPECT_TRUE(rate_settled(residuals));          // 0.77 .. 0.776
  EXPECT_FALSE(rate_settled({1.0, 0.5, 0.25}));  // two ratios say nothing yet
}

}  // namespace
}  // namespace mgelastic::grid

namespace mgelastic::grid {
namespace {

// FGMRES with one cycle per iteration reaches the same solution as plain cycles, in no more
// cycles, in both precisions.
TEST(MultigridSolve, AcceleratedSolveMatchesPlainCycles) {
  BoxSpec spec;
  spec.cells = 16;
  spec.poisson_ratio = 0.45;
  Multigrid<3, double> plain(make_box_problem<3>(spec));
  const SolveReport reference = plain.solve(1e-11, 60);
  Multigrid<3, double> accelerated(make_box_problem<3>(spec));
  const SolveReport report = accelerated.solve_accelerated(1e-11, 60);
  ASSERT_TRUE(reference.converged && report.converged);
  EXPECT_LE(report.cycles(), reference.cycles());
  EXPECT_LE(test::relative_displacement_difference(plain, accelerated), 1e-8);
  Multigrid<3, float> single(make_box_problem<3>(spec));
  EXPECT_TRUE(single.solve_accelerated(1e-8, 60).converged);
}

// Mixed precision keeps its Krylov basis in float (krylov_workspace.hpp): the restarts' true
// residuals in double absorb the basis' rounding, so a tight tolerance takes the cycles of the
// all-double solve, and the kept vectors take 4 doubles, 2 x restart + 1 floats and a 32-bit
// point per interior variable (before: 5 doubles + restart + 1 double basis vectors).
TEST(MultigridSolve, FloatKrylovBasisNeedsTheCyclesOfADoubleOne) {
  const BoxSpec spec{.cells = 24, .poisson_ratio = 0.48};
  constexpr int kRestart = 6;  // restarts happen before the tolerance
  Multigrid<3, double> all_double(make_box_problem<3>(spec));
  const SolveReport reference = all_double.solve_accelerated(1e-10, 80, kRestart);
  Multigrid<3, float> mixed(make_box_problem<3>(spec));
  const SolveReport report = mixed.solve_accelerated(1e-10, 80, kRestart);
  ASSERT_TRUE(reference.converged && report.converged);
  ASSERT_GT(report.cycles(), kRestart);
  EXPECT_LE(report.cycles(), reference.cycles() + 1);
  EXPECT_LE(test::relative_displacement_difference(all_double, mixed), 1e-8);

  std::size_t kept = 0;
  for (const ByteShare& share : mixed.byte_breakdown())
    if (share.name == "accelerated solve's vectors (kept)") kept = share.bytes;
  std::size_t interior = 0;
  const Level<3, double>& s = mixed.solution_level();
  for (int f = 0; f <= 3; ++f)
    for (std::size_t k = 0; k < s.size(); ++k) interior += s.kind(f, k) == VarKind::INTERIOR;
  ASSERT_GT(interior, 0u);
  const double per_variable = static_cast<double>(kept) / static_cast<double>(interior);
  // The points' vectors may hold up to twice their size (push_back).
  EXPECT_GE(per_variable, 4 * 8 + (2 * kRestart + 1) * 4 + 4);
  EXPECT_LE(per_variable, 4 * 8 + (2 * kRestart + 1) * 4 + 8);
}

// In double precision one level holds the solution and runs the cycles; its band rows carry the
// traction loads as constants. The preconditioning cycle must leave them out: with them it was
// affine, its vectors dominated by the loads' part (the Krylov vectors are unit vectors), and
// FGMRES lost to plain cycles (this bar: 18 against 14 cycles, now 13; a tip-loaded cantilever
// at 256 cells: 31 against 15 to 1e-9, now 14).
TEST(MultigridSolve, AcceleratedSolveWithTractionLoadsNeedsNoMoreCyclesThanPlainOnes) {
  // A 64 x 8 x 8 cantilever clamped at x = 0, sheared down at its free end, no body force.
  ElasticityProblem<3> bar = test::clamped_beam(IVec<3>(64, 8, 8));
  bar.body_force = [](const Vec<3>&) { return Vec<3>::Zero(); };
  bar.boundary_stress = [](int i, int j, const Vec<3>& x) {
    return i == 1 && j == 0 && x[0] > 0.99 ? -1e3 : 0.0;
  };
  Multigrid<3, double> plain(bar);
  bool constants = false;
  for (double c : plain.finest().band_kernel.constant) constants = constants || c != 0.0;
  ASSERT_TRUE(constants) << "the test needs traction constants in the band rows";
  const SolveReport reference = plain.solve(1e-9, 100);
  Multigrid<3, double> accelerated(bar);
  const SolveReport report = accelerated.solve_accelerated(1e-9, 100);
  ASSERT_TRUE(reference.converged && report.converged);
  EXPECT_LE(report.cycles(), reference.cycles());
  EXPECT_LE(test::relative_displacement_difference(plain, accelerated), 1e-6);
}

// The accelerated solve keeps its vectors and start storage for the next solve
// (krylov_workspace.hpp): a second solve after new loads equals, bit for bit, the same solve on
// a fresh hierarchy started from the same x, so nothing of the first solve carries over.
TEST(MultigridSolve, AcceleratedSolvesReuseTheirStorageWithoutCarryingState) {
  BoxSpec spec;
  spec.cells = 16;
  spec.poisson_ratio = 0.48;
  BoxSpec heavier = spec;
  heavier.body_force = 3.5e3;
  Multigrid<3, float> reused(make_box_problem<3>(spec));
  ASSERT_TRUE(reused.solve_accelerated(1e-6, 40, 4).converged);  // restarts included
  const auto first = reused.solution_state();
  reused.set_loads(make_box_problem<3>(heavier));
  const SolveReport second = reused.solve_accelerated(1e-8, 40, 4);

  Multigrid<3, float> fresh(make_box_problem<3>(heavier));
  fresh.set_solution_state(first);
  const SolveReport reference = fresh.solve_accelerated(1e-8, 40, 4);
  ASSERT_TRUE(reference.converged);
  EXPECT_GT(reference.cycles(), 2);
  EXPECT_EQ(second.residuals, reference.residuals);
  EXPECT_EQ(reused.solution_state(), fresh.solution_state());
}

// Mixed precision: add_correction leaves the float correction zero for the next cycle, which
// then skips zero_correction; whatever wrote the float level's x since (a caller through level(),
// an accelerated solve's cycles) makes the next cycle zero it again. Cycles after such a write
// must equal cycles that never saw it.
TEST(MultigridSolve, NextCycleStartsFromAZeroCorrection) {
  BoxSpec spec;
  spec.cells = 16;
  spec.poisson_ratio = 0.48;
  Multigrid<3, float> reference(make_box_problem<3>(spec));
  Multigrid<3, float> written(make_box_problem<3>(spec));
  for (int cycle = 0; cycle < 2; ++cycle) EXPECT_EQ(reference.vcycle(), written.vcycle());
  // Garbage in the float correction, through the mutable access.
  for (auto& field : written.level(0).x)
    for (std::size_t k = 0; k < field.size(); ++k) field[k] = 1e3f * static_cast<float>(k % 7);
  for (int cycle = 0; cycle < 2; ++cycle) EXPECT_EQ(reference.vcycle(), written.vcycle());

  // After an accelerated solve the float x holds its last cycle's correction.
  Multigrid<3, float> accelerated(make_box_problem<3>(spec));
  Multigrid<3, float> forced(make_box_problem<3>(spec));
  accelerated.solve_accelerated(1e-3, 4);
  forced.solve_accelerated(1e-3, 4);
  bool nonzero = false;
  for (const auto& field : accelerated.finest().x)
    for (std::size_t k = 0; k < field.size(); ++k) nonzero = nonzero || field[k] != 0.0f;
  ASSERT_TRUE(nonzero) << "the test needs a non-zero correction left by the solve";
  forced.level(0);  // forces zero_correction
  for (int cycle = 0; cycle < 2; ++cycle) EXPECT_EQ(forced.vcycle(), accelerated.vcycle());
}

// The options of a solve that refines after every cycle.
MultigridOptions refining_every_cycle() {
  MultigridOptions options;
  options.refinement_reduction = 1.0;
  return options;
}

// Mixed precision inside solve(): the float cycles go on with one correction problem until its
// residual fell to refinement_reduction of where it started (MultigridOptions), so fewer
// cycles pay the refinement. The solve needs no more cycles than one that refines after every
// cycle, each deferred cycle's float residual is the double one to round-off, and the last
// entry is the double residual of the returned solution.
TEST(MultigridSolve, DeferredRefinementKeepsTheCyclesAndTheResidual) {
  Multigrid<3, float> deferred(test::mixed_box(32));
  Multigrid<3, float> refined(test::mixed_box(32), refining_every_cycle());
  const SolveReport a = deferred.solve(1e-10, 40);
  const SolveReport b = refined.solve(1e-10, 40);
  ASSERT_TRUE(a.converged);
  ASSERT_TRUE(b.converged);
  EXPECT_LE(a.cycles(), b.cycles());
  EXPECT_EQ(b.cycles(), refined.refinements());
  EXPECT_LT(deferred.refinements(), a.cycles() / 2);
  EXPECT_GT(deferred.float_norms(), a.cycles() / 2);
  // Each entry against the refining solve's, while both are well above the double floor.
  for (int c = 0; c <= std::min(a.cycles(), b.cycles()); ++c) {
    if (b.residuals[c] > 1e-8 * b.residuals.front()) {
      EXPECT_NEAR(a.residuals[c] / b.residuals[c], 1.0, 0.05) << "cycle " << c;
    }
  }
  EXPECT_EQ(a.residuals.back(), deferred.residual());  // the double residual, recomputed
}

// A solve whose cycle limit comes in the middle of a deferred refinement refines on its last
// cycle (without a float norm): the solution and its reported residual are those of every cycle
// run, and a fixed number of cycles (time steps' vcycles_per_step) pays no float norm at the end.
TEST(MultigridSolve, CycleLimitAddsThePendingCorrection) {
  Multigrid<3, float> deferred(test::mixed_box(16));
  Multigrid<3, float> refined(test::mixed_box(16), refining_every_cycle());
  // Cycle 1 refines (no ratio known yet); cycle 2's float residual (0.21 of the refined one)
  // defers its refinement, which the last cycle makes.
  const SolveReport a = deferred.run_cycles(3);
  const SolveReport b = refined.run_cycles(3);
  EXPECT_EQ(deferred.float_norms(), 1);
  EXPECT_EQ(deferred.refinements(), 2);
  Multigrid<3, float> two(test::mixed_box(16));
  two.run_cycles(2);
  EXPECT_EQ(two.float_norms(), 0);
  EXPECT_EQ(two.refinements(), 2);
  EXPECT_EQ(a.residuals.back(), deferred.residual());
  EXPECT_NEAR(a.residuals.back() / b.residuals.back(), 1.0, 1e-3);
  double largest = 0, difference = 0;
  for (int f = 0; f <= 3; ++f)
    for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(deferred.finest().size()); ++k) {
      largest = std::max(largest, std::abs(refined.solution(f, k)));
      difference = std::max(difference, std::abs(deferred.solution(f, k) - refined.solution(f, k)));
    }
  ASSERT_GT(largest, 0.0);
  EXPECT_LT(difference, 1e-4 * largest);  // a lost correction would be ~10 %
}

}  // namespace
}  // namespace mgelastic::grid
