// Re-use of a hierarchy across frames; the rule that picks the coarsest level. (Dropping a
// singular coarsest level: Coarsening.PatchThatCoarsensIntoAHingeKeepsARepairedCoarseLevel.)
#include <gtest/gtest.h>

#include "mgelastic/grid/box_problem.hpp"
#include "mgelastic/grid/convergence_rate.hpp"
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

// A plate 64 x 64 x 8 cells, held along one edge: its 16 x 16 x 2 level is all boundary cells
// (traction boundaries half a coarse cell inside a body two cells thick), so the hierarchy stops
// one level finer, which also converges faster (0.21 per cycle against 0.29).
TEST(MultigridSetup, HierarchyStopsBeforeALevelOfMostlyBoundaryCells) {
  ElasticityProblem<3> plate = make_box_problem<3>({.cells = 8, .poisson_ratio = 0.3});
  plate.lattice = Lattice<3>(IVec<3>(64, 64, 8), 1.0 / 64);
  plate.cells.assign(plate.lattice.size(), CellType::EXTERIOR);
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(plate.lattice.size()); ++k) {
    const IVec<3> s = plate.lattice.coords(k);
    if (plate.lattice.is_real(s))
      plate.cells[k] = s[0] <= 2 ? CellType::DIRICHLET : CellType::INTERIOR;
  }
  Multigrid<3, double> stopped(plate);
  Multigrid<3, double> deeper(plate, {.coarsest_max_boundary_fraction = 1.0});
  EXPECT_EQ(stopped.levels(), 2);
  EXPECT_EQ(deeper.levels(), 3);
  EXPECT_LT(convergence_rate(stopped.run_cycles(12).residuals),
            convergence_rate(deeper.run_cycles(12).residuals));
}

}  // namespace
}  // namespace mgelastic::grid
