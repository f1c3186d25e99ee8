// Re-use of a hierarchy across frames; the rule that picks the coarsest level. (Dropping a
// singular coarsest level: Coarsening.PatchThatCoarsensIntoAHingeKeepsARepairedCoarseLevel.)
#include <gtest/gtest.h>

#include <random>

#include "grid_test_support.hpp"
#include "mgelastic/grid/boundary_smoother.hpp"
#include "mgelastic/grid/box_problem.hpp"
#include "mgelastic/grid/convergence_rate.hpp"
#include "mgelastic/grid/multigrid.hpp"
#include "mgelastic/grid/residual.hpp"

namespace mgelastic::grid {
namespace {

double max_difference(const Multigrid<3, double>& a, const Multigrid<3, double>& b) {
  double worst = 0;
  const auto& level = a.finest();
  for (int f = 0; f < 3; ++f)
    for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(level.size()); ++k)
      if (level.kind(f, k) != VarKind::INACTIVE)
        worst = std::max(worst, std::abs(a.solution(f, k) - b.solution(f, k)));
  return worst;
}

// A new Dirichlet displacement on an existing hierarchy (the next frame of a keyframed region),
// solved from the old solution, gives the solution of a hierarchy built for it from scratch.
TEST(MultigridSetup, NewDirichletDisplacementMatchesAFreshSolve) {
  ElasticityProblem<3> problem = make_box_problem<3>({.cells = 16, .poisson_ratio = 0.4});
  const auto pulled = [](const Vec<3>& x) { return Vec<3>(0.01 * x.y(), 0.02, -0.01 * x.z()); };
  Multigrid<3, double> reused(problem);
  ASSERT_TRUE(reused.solve(1e-10, 40).converged);
  reused.set_dirichlet_displacement(pulled);
  ASSERT_TRUE(reused.solve(1e-10, 40).converged);
  problem.dirichlet_displacement = pulled;
  Multigrid<3, double> fresh(problem);
  ASSERT_TRUE(fresh.solve(1e-10, 40).converged);
  EXPECT_LT(max_difference(reused, fresh), 1e-8);
}

// Mixed precision: the double solution level reads the float finest level's variable kinds and
// relaxation classes (one copy, counted once), and a copied level owns its own again.
TEST(MultigridSetup, SolutionLevelSharesTheFinestLevelsVariableCodes) {
  const ElasticityProblem<3> problem = make_box_problem<3>({.cells = 16, .poisson_ratio = 0.45});
  Multigrid<3, float> mg(problem);
  const Level<3, float>& fine = mg.finest();
  const Level<3, double>& solution = mg.solution_level();
  EXPECT_EQ(solution.codes.data(), fine.codes.data());
  EXPECT_TRUE(fine.codes.owns());
  EXPECT_FALSE(solution.codes.owns());
  bool counted = false;
  for (const ByteShare& share : solution.byte_breakdown())
    if (share.name == "variable codes (kind, relaxation)") {
      EXPECT_EQ(share.bytes, 0u);
      counted = true;
    }
  EXPECT_TRUE(counted);
  for (const ByteShare& share : fine.byte_breakdown())
    if (share.name == "variable codes (kind, relaxation)") {
      EXPECT_EQ(share.bytes, fine.codes.bytes());
      EXPECT_GE(share.bytes, fine.size() * sizeof(VarCode));
    }
  Level<3, double> copy = solution;
  ASSERT_EQ(copy.codes.codes(), fine.codes.codes());
  EXPECT_NE(copy.codes.data(), fine.codes.data());
  EXPECT_TRUE(copy.codes.owns());
  copy.codes.set_kind(0, 0, VarKind::INTERIOR);
  EXPECT_EQ(copy.kind(0, 0), VarKind::INTERIOR);
  EXPECT_EQ(fine.kind(0, 0), VarKind::INACTIVE);  // the corner ghost point
  EXPECT_TRUE(mg.solve(1e-8, 30).converged);
}

// The solution level takes the finest level's codes instead of classifying again
// (build_solution_level): it must be the level build_level gives for the same typing, loads
// and boundary stress. Compared by what its rows and rules do: the traction faces they set and
// the residual of random values, both bit for bit.
TEST(MultigridSetup, SolutionLevelFromTheFinestCodesEqualsAFreshBuild) {
  ElasticityProblem<3> problem = test::clamped_ball(20);
  problem.boundary_stress = [](int i, int j, const Vec<3>& x) {
    return i == j ? 300.0 * x[2] : 40.0 * x[i];
  };
  Multigrid<3, float> mg(problem);
  ASSERT_GT(mg.levels(), 1);
  Level<3, double> shared = mg.solution_level();
  Level<3, double> fresh = build_level<3, double>(
      problem.lattice, problem.cells, problem.material, problem.boundary_stress, &mg.level(1).cells,
      problem.inertia, mg.options().band_layers, {}, 0.0, {}, true, LevelUse::RESIDUAL);
  ASSERT_TRUE(fresh.codes.same_values(shared.codes));
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int f = 0; f <= 3; ++f)
    for (std::size_t k = 0; k < fresh.size(); ++k) {
      const bool variable = fresh.kind(f, static_cast<std::ptrdiff_t>(k)) != VarKind::INACTIVE;
      const double x = variable ? uniform(rng) : 0.0, b = variable ? uniform(rng) : 0.0;
      shared.x[f][k] = fresh.x[f][k] = x;
      shared.b[f][k] = fresh.b[f][k] = b;
    }
  back_substitute_traction(shared);
  back_substitute_traction(fresh);
  for (int f = 0; f <= 3; ++f) ASSERT_EQ(shared.x[f], fresh.x[f]) << "field " << f;
  EXPECT_EQ(fresh_residual_norm(shared), fresh_residual_norm(fresh));
  EXPECT_GT(fresh_residual_norm(fresh), 0.0);
}

// A plate 64 x 64 x 8 cells, held along one edge: its 16 x 16 x 2 level is all boundary cells
// (traction boundaries half a coarse cell inside a body two cells thick), so the hierarchy stops
// one level finer, which also converges faster (0.21 per cycle against 0.29).
TEST(MultigridSetup, HierarchyStopsBeforeALevelOfMostlyBoundaryCells) {
  const ElasticityProblem<3> plate = test::clamped_beam(IVec<3>(64, 64, 8));
  Multigrid<3, double> stopped(plate);
  Multigrid<3, double> deeper(plate, {.coarsest_max_boundary_fraction = 1.0});
  EXPECT_EQ(stopped.levels(), 2);
  EXPECT_EQ(deeper.levels(), 3);
  EXPECT_LT(convergence_rate(stopped.run_cycles(12).residuals),
            convergence_rate(deeper.run_cycles(12).residuals));
}

// A slender bar stops coarsening early under the boundary rule (a 6 x 6 section is 56 % boundary
// cells), at a level that holds an eighth of its cells: its direct solve then outweighs the
// cycle (a 256 x 26 x 26 cantilever: 2.2 s to factor, half of each cycle, half of the peak
// memory). Such a level is coarsened once more, at a small cost in rate.
TEST(MultigridSetup, SlenderBarCoarsensPastTheBoundaryRuleWhereTheDirectSolveWouldDominate) {
  const ElasticityProblem<3> bar = test::clamped_beam(IVec<3>(256, 24, 24));
  Multigrid<3, double> deeper(bar);
  Multigrid<3, double> two_levels(bar, {.max_levels = 2});
  EXPECT_EQ(deeper.levels(), 3);
  const double rate = convergence_rate(deeper.run_cycles(10).residuals);
  const double two_level_rate = convergence_rate(two_levels.run_cycles(10).residuals);
  EXPECT_LE(rate, 0.35);  // 0.272 (two levels: 0.208)
  EXPECT_LE(rate, two_level_rate + 0.1);
}

}  // namespace
}  // namespace mgelastic::grid
