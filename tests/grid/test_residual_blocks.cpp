#include "mgelastic/grid/residual_blocks.hpp"

#include <gtest/gtest.h>

#include "mgelastic/core/error.hpp"
#include "mgelastic/grid/box_problem.hpp"
#include "mgelastic/grid/coarsening.hpp"

namespace mgelastic::grid {
namespace {

Level<3, double> zero_mixed_box(int cells) {
  BoxSpec spec;
  spec.cells = cells;
  spec.poisson_ratio = 0.48;
  const auto problem = make_box_problem<3>(spec);
  const auto coarse_cells = coarsen_cells(problem.lattice, problem.cells);
  auto level =
      build_level<3, double>(problem.lattice, problem.cells, problem.material, {}, &coarse_cells);
  for (int f = 0; f <= 3; ++f) {
    std::fill(level.x[f].begin(), level.x[f].end(), 0.0);
    std::fill(level.b[f].begin(), level.b[f].end(), 0.0);
  }
  return level;
}

// With x = 0 the residual is b: two loads in two cubes give the cubes' shares 16/25 and 9/25,
// in that order, at the cubes' first cells; one cell per cube gives the cells themselves.
TEST(ResidualBlocks, FindTheCubesHoldingTheResidual) {
  Level<3, double> level = zero_mixed_box(16);
  const IVec<3> near{5, 9, 6}, far{12, 11, 10};
  const std::ptrdiff_t k_near = level.lattice.index(near), k_far = level.lattice.index(far);
  ASSERT_EQ(level.kind(0, k_near), VarKind::INTERIOR);
  ASSERT_EQ(level.kind(3, k_far), VarKind::INTERIOR);
  level.b[0][k_near] = 3.0;
  level.b[3][k_far] = -4.0;

  const auto blocks = residual_blocks<3>(level, 8, 10);
  ASSERT_EQ(blocks.size(), 2u);
  const double total = 9.0 + 16.0;
  EXPECT_EQ(blocks[0].first, (std::array<int, 3>{8, 8, 8}));
  EXPECT_NEAR(blocks[0].share, 16.0 / total, 1e-12);
  EXPECT_EQ(blocks[1].first, (std::array<int, 3>{0, 8, 0}));
  EXPECT_NEAR(blocks[1].share, 9.0 / total, 1e-12);

  const auto cells = residual_blocks<3>(level, 1, 1);
  ASSERT_EQ(cells.size(), 1u);
  EXPECT_EQ(cells[0].first, (std::array<int, 3>{12, 11, 10}));
  EXPECT_THROW(residual_blocks<3>(level, 0, 1), Error);
}

TEST(ResidualBlocks, ZeroResidualHasNoBlocks) {
  const Level<3, double> level = zero_mixed_box(8);
  EXPECT_TRUE(residual_blocks<3>(level, 4, 5).empty());
}

// Loads on three chosen variables (x = 0, so the residual is b): one face next to the clamp, one
// pressure next to the traction surface, one deep inside. The shares follow the loads' squares,
// per field and per place.
TEST(ResidualShares, SplitTheResidualByFieldAndPlace) {
  Level<3, double> level = zero_mixed_box(16);  // Dirichlet slab: stored x 1 .. 2
  const std::ptrdiff_t by_clamp = level.lattice.index(IVec<3>{4, 8, 8});     // u_x face, cells 3|4
  const std::ptrdiff_t by_surface = level.lattice.index(IVec<3>{9, 16, 8});  // top cell layer
  const std::ptrdiff_t inside = level.lattice.index(IVec<3>{9, 8, 8});
  ASSERT_EQ(level.kind(0, by_clamp), VarKind::INTERIOR);
  ASSERT_EQ(level.kind(3, by_surface), VarKind::INTERIOR);
  ASSERT_EQ(level.kind(1, inside), VarKind::INTERIOR);
  level.b[0][by_clamp] = 1.0;
  level.b[3][by_surface] = 2.0;
  level.b[1][inside] = 3.0;

  const ResidualShares<3> shares = residual_shares<3>(level);
  const double total = 1.0 + 4.0 + 9.0;
  EXPECT_NEAR(shares.field[0], 1.0 / total, 1e-12);
  EXPECT_NEAR(shares.field[1], 9.0 / total, 1e-12);
  EXPECT_EQ(shares.field[2], 0.0);
  EXPECT_NEAR(shares.field[3], 4.0 / total, 1e-12);
  EXPECT_NEAR(shares.next_to_dirichlet, 1.0 / total, 1e-12);
  EXPECT_NEAR(shares.next_to_exterior, 4.0 / total, 1e-12);
  EXPECT_NEAR(shares.elsewhere, 9.0 / total, 1e-12);
}

TEST(ResidualShares, ZeroResidualHasZeroShares) {
  const ResidualShares<3> shares = residual_shares<3>(zero_mixed_box(8));
  EXPECT_EQ(shares.next_to_dirichlet + shares.next_to_exterior + shares.elsewhere, 0.0);
}

}  // namespace
}  // namespace mgelastic::grid
