#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "grid_test_support.hpp"
#include "mgelastic/grid/band_block_shapes.hpp"
#include "mgelastic/grid/boundary_smoother.hpp"
#include "mgelastic/grid/multigrid.hpp"

namespace mgelastic::grid {
namespace {

// Random values on every variable of the level (the sums below read them all).
template <typename Scalar>
void randomize(Level<3, Scalar>& level) {
  std::mt19937 rng(5);
  std::normal_distribution<double> normal;
  for (auto& field : level.x)
    for (auto& v : field) v = static_cast<Scalar>(normal(rng));
}

// Each block member's dense sum (band_block_shapes.hpp) equals its pattern row's sum up to the
// round-off of another order: a wrong column, offset or lane would differ by O(1).
TEST(BandBlockShapes, DenseSumsEqualThePatternRows) {
  Multigrid<3, double> mg(test::clamped_ball(32));
  Level<3, double> level = mg.finest();
  const auto& shapes = level.band_block_shapes;
  ASSERT_TRUE(shapes.built_for(level.band_blocks.size()));
  EXPECT_LT(shapes.shapes(), level.band_blocks.size());  // 581 for 1780 blocks
  randomize(level);
  std::array<const double*, 4> x{};
  for (int f = 0; f < 4; ++f) x[f] = level.x[f].data();
  address_entries<double>(level.band_kernel, {x.data(), x.size()});
  address_columns<double>(level.band_block_shapes, {x.data(), x.size()});
  double worst = 0;
  std::size_t members = 0;
  for (std::size_t e = 0; e < level.band_blocks.size(); ++e) {
    const auto& block = level.band_blocks[e];
    double sums[BandBlockShapes<double>::kLanes];
    shapes.row_sums(x[0], level.band_kernel.target[block[0]], e, sums);
    for (int a = 0; a < 6 && block[a] != UINT32_MAX; ++a, ++members) {
      const double expected = level.band_kernel.row_sum(level.x, block[a]);
      worst = std::max(worst, std::abs(sums[a] - expected) / (1.0 + std::abs(expected)));
    }
  }
  EXPECT_GT(members, 2 * level.band_blocks.size());
  EXPECT_LT(worst, 1e-12);
}

// The band sweeps through the dense blocks equal those through the pattern rows to round-off.
TEST(BandBlockShapes, SweepsEqualThePatternPath) {
  Multigrid<3, double> mg(test::clamped_ball(32));
  Level<3, double> dense = mg.finest();
  randomize(dense);
  refresh_band_rhs(dense);
  Level<3, double> patterns = dense;
  patterns.band_block_shapes = {};
  band_gauss_seidel(dense, 3, BandSweepOrder::BLOCK_LOCAL, BandRhs::CURRENT);
  band_gauss_seidel(patterns, 3, BandSweepOrder::BLOCK_LOCAL, BandRhs::CURRENT);
  double worst = 0, scale = 0;
  for (int f = 0; f < 4; ++f)
    for (std::size_t k = 0; k < dense.size(); ++k) {
      worst = std::max(worst, std::abs(dense.x[f][k] - patterns.x[f][k]));
      scale = std::max(scale, std::abs(patterns.x[f][k]));
    }
  EXPECT_GT(scale, 0.1);
  EXPECT_LT(worst, 1e-10 * scale);
}

}  // namespace
}  // namespace mgelastic::grid
