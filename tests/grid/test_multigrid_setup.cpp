// Re-use of a hierarchy across frames. (Dropping a singular coarsest level is exercised by
// RealScans.BunnyUnderGravitySolvesToOneInAMillion, whose 16^3 level is singular.)
#include <gtest/gtest.h>

#include "mgelastic/grid/box_problem.hpp"
#include "mgelastic/grid/multigrid.hpp"

namespace mgelastic::grid {
namespace {

double max_difference(const Multigrid<3, double>& a, const Multigrid<3, double>& b) {
  double worst = 0;
  const auto& level = a.finest();
  for (int f = 0; f < 3; ++f)
    for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(level.size()); ++k)
      if (level.kind[f][k] != VarKind::INACTIVE)
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

}  // namespace
}  // namespace mgelastic::grid
