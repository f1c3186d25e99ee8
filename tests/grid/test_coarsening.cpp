// Cell typings with hinges and thin sheets (geometry/rigid_blocks.hpp): their strain-free modes
// make the staggered system singular; repair_coarse_cells() (used on every coarse level, and the
// same rule voxelize() applies to the finest) removes them with a few filled cells.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>

#include "mgelastic/grid/coarse_solver.hpp"
#include "mgelastic/grid/coarsening.hpp"
#include "mgelastic/grid/multigrid.hpp"

namespace mgelastic::grid {
namespace {

// n cells per axis (h = 1/16), cells where `body(s)` holds (stored coordinates s) are interior,
// cells of the body with s_z == 1 are Dirichlet; gravity along -z.
template <int Dim>
ElasticityProblem<Dim> typed_problem(const IVec<Dim>& n,
                                     const std::function<bool(const IVec<Dim>&)>& body) {
  ElasticityProblem<Dim> problem;
  problem.lattice = Lattice<Dim>(n, 1.0 / 16);
  problem.material = {1e5, 0.3};
  problem.cells.assign(problem.lattice.size(), CellType::EXTERIOR);
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(problem.lattice.size()); ++k) {
    const IVec<Dim> s = problem.lattice.coords(k);
    if (!problem.lattice.is_real(s) || !body(s)) continue;
    problem.cells[k] = s[Dim - 1] == 1 ? CellType::DIRICHLET : CellType::INTERIOR;
  }
  problem.body_force = [](const Vec<Dim>&) {
    Vec<Dim> f = Vec<Dim>::Zero();
    f[Dim - 1] = -1e3;
    return f;
  };
  return problem;
}

bool in_box(const IVec<3>& s, const IVec<3>& lo, const IVec<3>& hi) {
  return (s.array() >= lo.array()).all() && (s.array() < hi.array()).all();
}

// A held 4^3 cube A and a free 4^3 cube B that touches it through a single cell face, or
// through a strip one cell wide and four long.
ElasticityProblem<3> hinged_cubes(bool strip) {
  const IVec<3> b_lo(5, strip ? 1 : 4, 4);
  return typed_problem<3>(IVec<3>(10, 8, 8), [b_lo](const IVec<3>& s) {
    return in_box(s, IVec<3>(1, 1, 1), IVec<3>(5, 5, 5)) ||
           in_box(s, b_lo, b_lo + IVec<3>(4, 4, 4));
  });
}

int direct_solve_rejected(const ElasticityProblem<3>& problem) {
  try {
    Multigrid<3, double> direct(problem, {.max_levels = 1});
  } catch (const SingularCoarseLevel&) {
    return 1;
  }
  return 0;
}

TEST(Coarsening, HingedPartsMakeTheLatticeSingular) {
  for (bool strip : {false, true}) {
    SCOPED_TRACE(strip ? "strip hinge" : "single-face hinge");
    EXPECT_EQ(direct_solve_rejected(hinged_cubes(strip)), 1);
  }
}

// The repair chains the full 2x2x2 blocks of both cubes through a few filled cells; the
// finest level alone (a CHOLMOD solve with its condition check) is then non-singular.
TEST(Coarsening, RepairedHingesAreNonSingular) {
  for (bool strip : {false, true}) {
    SCOPED_TRACE(strip ? "strip hinge" : "single-face hinge");
    ElasticityProblem<3> problem = hinged_cubes(strip);
    const int added = repair_coarse_cells(problem.lattice, problem.cells);
    EXPECT_GT(added, 0);
    EXPECT_LE(added, 8);
    EXPECT_EQ(direct_solve_rejected(problem), 0);
    Multigrid<3, double> direct(problem, {.max_levels = 1});
    EXPECT_TRUE(direct.solve(1e-8, 2).converged);
  }
}

// The 2D rule: two held/free squares hinged at one cell face.
TEST(Coarsening, RepairedHingeIsNonSingularIn2D) {
  const auto body = [](const IVec<2>& s) {
    return (s[0] <= 4 && s[1] <= 4) || (s[0] >= 5 && s[0] <= 8 && s[1] >= 4 && s[1] <= 7);
  };
  ElasticityProblem<2> problem = typed_problem<2>(IVec<2>(10, 8), body);
  EXPECT_THROW((Multigrid<2, double>(problem, {.max_levels = 1})), SingularCoarseLevel);
  EXPECT_GT(repair_coarse_cells(problem.lattice, problem.cells), 0);
  EXPECT_NO_THROW((Multigrid<2, double>(problem, {.max_levels = 1})));
}

// Two 6^3 cubes touching through a 2x2 patch of faces aligned with the coarse cells: rigid on
// the fine level (the blocks across the patch chain them), hinged at a single face on the coarse
// level. Unrepaired, that level is singular and dropped (the finest level is then solved
// directly); repaired, the hierarchy keeps it. The repaired joint (2x2 coarse cells) is stiffer
// than the fine one, so plain cycles converge slowly here (0.88); accelerated ones converge.
TEST(Coarsening, PatchThatCoarsensIntoAHingeKeepsARepairedCoarseLevel) {
  const ElasticityProblem<3> problem = typed_problem<3>(IVec<3>(14, 12, 12), [](const IVec<3>& s) {
    return in_box(s, IVec<3>(1, 1, 1), IVec<3>(7, 7, 7)) ||   // held cube
           in_box(s, IVec<3>(7, 5, 5), IVec<3>(13, 11, 11));  // free cube
  });
  EXPECT_EQ((Multigrid<3, double>(problem, {.repair_coarse_cells = false}).levels()), 1);
  Multigrid<3, double> repaired(problem);
  EXPECT_EQ(repaired.levels(), 2);
  EXPECT_TRUE(repaired.solve_accelerated(1e-6, 40).converged);
}

// Decision 8a's walls on clamps whose top lies between coarse faces (a flat clamp of t finest
// rows, top at z = t): the entry of the coarse Dirichlet cell's upper z face is 1 + the finest
// layers between its face and the finest wall, on every level; where the first layer with a
// Dirichlet cell is only partly Dirichlet (a stepped clamp top inside the coarse cell), 0.
TEST(Coarsening, WallLayersLocateAMisalignedClampTop) {
  const Lattice<3> finest(IVec<3>(8, 8, 8), 1.0);
  const auto walls = [&](const std::function<int(const IVec<3>&)>& top, int levels,
                         const IVec<3>& coarse_cell) {
    std::vector<CellType> cells(finest.size(), CellType::EXTERIOR);
    for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(finest.size()); ++k) {
      const IVec<3> s = finest.coords(k);
      if (finest.is_real(s)) cells[k] = s[2] <= top(s) ? CellType::DIRICHLET : CellType::INTERIOR;
    }
    Lattice<3> lattice = finest;
    std::vector<CellType> coarse = cells;
    for (int l = 0; l < levels; ++l) {
      coarse = coarsen_cells(lattice, coarse);
      lattice = coarsen(lattice);
    }
    EXPECT_EQ(coarse[lattice.index(coarse_cell)], CellType::DIRICHLET);
    const std::vector<std::uint8_t> w =
        finest_dirichlet_wall_layers(finest, cells, lattice, coarse, 1 << levels);
    return static_cast<int>(w[lattice.index(coarse_cell) * 6 + 2 * 2 + 1]);
  };
  const auto flat = [](int t) { return [t](const IVec<3>&) { return t; }; };
  EXPECT_EQ(walls(flat(2), 1, IVec<3>(2, 2, 1)), 1);  // aligned: the coarse wall is the finest
  EXPECT_EQ(walls(flat(3), 1, IVec<3>(2, 2, 2)), 2);  // one finest layer below the coarse wall
  EXPECT_EQ(walls(flat(3), 2, IVec<3>(1, 1, 1)), 2);
  EXPECT_EQ(walls(flat(1), 2, IVec<3>(1, 1, 1)), 4);  // three layers below
  EXPECT_EQ(walls(flat(4), 2, IVec<3>(1, 1, 1)), 1);
  // Top at 3 for x <= 3, at 2 beyond: the coarse cell x 3-4 has a stepped top.
  const auto stepped = [](const IVec<3>& s) { return s[0] <= 3 ? 3 : 2; };
  EXPECT_EQ(walls(stepped, 1, IVec<3>(1, 1, 2)), 2);
  EXPECT_EQ(walls(stepped, 1, IVec<3>(2, 1, 2)), 0);
  EXPECT_EQ(walls(stepped, 1, IVec<3>(3, 1, 1)), 1);
}

// Boxes need no repair: their coarse typings stay exactly the coarsened ones.
TEST(Coarsening, RepairLeavesBoxesUnchanged) {
  ElasticityProblem<3> box = typed_problem<3>(
      IVec<3>(12, 10, 8), [](const IVec<3>& s) { return s[0] >= 2 && s[1] >= 3 && s[2] <= 6; });
  std::vector<CellType> coarse = coarsen_cells(box.lattice, box.cells);
  const std::vector<CellType> before = coarse;
  EXPECT_EQ(repair_coarse_cells(coarsen(box.lattice), coarse), 0);
  EXPECT_TRUE(coarse == before);
}

}  // namespace
}  // namespace mgelastic::grid
