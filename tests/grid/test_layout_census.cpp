// The layout census (grid/layout_census.hpp) against a direct count: a set of the tiles around
// every variable, point by point, on embedded and box levels in 2D and 3D.
#include <gtest/gtest.h>

#include <set>

#include "grid_test_support.hpp"
#include "mgelastic/grid/box_problem.hpp"
#include "mgelastic/grid/layout_census.hpp"
#include "mgelastic/grid/multigrid.hpp"

namespace mgelastic::grid {
namespace {

const std::vector<std::array<int, 3>> kSizes{{4, 4, 4}, {8, 8, 8}, {32, 8, 4}, {3, 5, 7}};

template <int Dim, typename Scalar>
bool has_variable(const Level<Dim, Scalar>& level, std::ptrdiff_t k) {
  for (int f = 0; f <= Dim; ++f)
    if (level.kind(f, k) != VarKind::INACTIVE) return true;
  return false;
}

// The tiles that hold a variable or one of the 3^Dim points around one, by brute force.
template <int Dim, typename Scalar>
std::size_t direct_tiles(const Level<Dim, Scalar>& level, const std::array<int, 3>& size) {
  const Lattice<Dim>& lattice = level.lattice;
  std::set<std::array<int, Dim>> tiles;
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(level.size()); ++k) {
    if (!has_variable(level, k)) continue;
    const IVec<Dim> s = lattice.coords(k);
    const int around = Dim == 3 ? 27 : 9;
    for (int n = 0; n < around; ++n) {
      std::array<int, Dim> tile{};
      bool inside = true;
      for (int a = 0, code = n; a < Dim; ++a, code /= 3) {
        const int c = s[a] + code % 3 - 1;
        inside = inside && c >= 0 && c < lattice.padded(a);
        tile[a] = c / size[a];
      }
      if (inside) tiles.insert(tile);
    }
  }
  return tiles.size();
}

template <int Dim, typename Scalar>
void expect_matches_direct_count(const Level<Dim, Scalar>& level) {
  const LayoutCensus census = layout_census(level, kSizes);
  std::size_t variables = 0, pages = 0;
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(level.size()); ++k)
    variables += has_variable(level, k) ? 1 : 0;
  for (std::ptrdiff_t page = 0; page * 1024 < static_cast<std::ptrdiff_t>(level.size()); ++page) {
    bool any = false;
    for (std::ptrdiff_t k = page * 1024;
         k < std::min<std::ptrdiff_t>((page + 1) * 1024, level.size()); ++k)
      any = any || has_variable(level, k);
    pages += any ? 1024 : 0;
  }
  // One x-range per storage row, from its first to its last point next to a variable.
  std::size_t ranges = 0;
  const std::ptrdiff_t n = level.lattice.padded(0);
  for (std::ptrdiff_t row = 0; row < static_cast<std::ptrdiff_t>(level.size()); row += n) {
    std::ptrdiff_t lo = n, hi = -1;
    for (std::ptrdiff_t i = 0; i < n; ++i) {
      bool near = false;
      const IVec<Dim> s = level.lattice.coords(row + i);
      for (int m = 0; m < (Dim == 3 ? 27 : 9) && !near; ++m) {
        IVec<Dim> t = s;
        bool inside = true;
        for (int a = 0, code = m; a < Dim; ++a, code /= 3) {
          t[a] += code % 3 - 1;
          inside = inside && t[a] >= 0 && t[a] < level.lattice.padded(a);
        }
        near = inside && has_variable(level, level.lattice.index(t));
      }
      if (near) lo = std::min(lo, i), hi = std::max(hi, i);
    }
    if (hi >= 0) ranges += static_cast<std::size_t>(hi - lo + 1);
  }
  EXPECT_EQ(census.row_ranges, ranges);
  EXPECT_GE(census.row_ranges, census.with_variables);
  EXPECT_LE(census.row_ranges, census.bounding_box);
  EXPECT_EQ(census.bounding_box, level.size());
  EXPECT_EQ(census.with_variables, variables);
  EXPECT_EQ(census.live_pages, pages);
  ASSERT_EQ(census.tiles.size(), kSizes.size());
  for (std::size_t t = 0; t < kSizes.size(); ++t) {
    int points = 1;
    for (int a = 0; a < Dim; ++a) points *= kSizes[t][a];
    EXPECT_EQ(census.tiles[t].tiles, direct_tiles(level, kSizes[t])) << "tile size " << t;
    EXPECT_EQ(census.tiles[t].points, census.tiles[t].tiles * points);
    // No layout keeps fewer points than those with a variable, none more than the box.
    EXPECT_GE(census.tiles[t].points, census.with_variables);
  }
  EXPECT_LE(census.with_variables, census.live_pages);
}

TEST(LayoutCensus, MatchesADirectCountOnTheClampedBallsLevels) {
  Multigrid<3, float> mg(test::clamped_ball(24));
  ASSERT_GE(mg.levels(), 2);
  for (int l = 0; l < mg.levels(); ++l) expect_matches_direct_count(mg.level(l));
}

TEST(LayoutCensus, MatchesADirectCountIn2D) {
  BoxSpec spec;
  spec.cells = 24;
  Multigrid<2, double> mg(make_box_problem<2>(spec));
  for (int l = 0; l < mg.levels(); ++l) expect_matches_direct_count(mg.level(l));
}

TEST(LayoutCensus, FollowsTheBodyWhereTheBoxFillsItsLattice) {
  BoxSpec spec;
  spec.cells = 32;
  Multigrid<3, float> box(make_box_problem<3>(spec));
  Multigrid<3, float> ball(test::clamped_ball(32));
  const LayoutCensus full = layout_census(box.finest(), kSizes);
  const LayoutCensus embedded = layout_census(ball.finest(), kSizes);
  // The box: nearly every point holds a variable, every tile is needed.
  EXPECT_GT(full.with_variables, 0.9 * full.bounding_box);
  EXPECT_GE(full.tiles[0].points, full.bounding_box);
  // The ball fills ~pi/6 of its box: the 4^3 tiles keep well under the box's points.
  EXPECT_LT(embedded.tiles[0].points, 0.85 * embedded.bounding_box);
  EXPECT_LT(embedded.tiles[0].points, embedded.tiles[1].points + 1);  // 4^3 nest in 8^3
  // One x-range per row drops the box's corners around the ball, keeps the box whole.
  EXPECT_LT(embedded.row_ranges, 0.85 * embedded.bounding_box);
  EXPECT_EQ(full.row_ranges, full.bounding_box);
}

TEST(LayoutCensus, SumsTheLevels) {
  Multigrid<3, float> mg(test::clamped_ball(24));
  std::vector<const Level<3, float>*> levels;
  LayoutCensus sum;
  for (int l = 0; l < mg.levels(); ++l) {
    levels.push_back(&static_cast<const Multigrid<3, float>&>(mg).level(l));
    const LayoutCensus one = layout_census(mg.level(l), kSizes);
    sum.bounding_box += one.bounding_box;
    sum.with_variables += one.with_variables;
    sum.row_ranges += one.row_ranges;
  }
  const LayoutCensus total = layout_census(levels, kSizes);
  EXPECT_EQ(total.bounding_box, sum.bounding_box);
  EXPECT_EQ(total.with_variables, sum.with_variables);
  EXPECT_EQ(total.row_ranges, sum.row_ranges);
  EXPECT_EQ(total.active_cells, layout_census(mg.finest(), kSizes).active_cells);
}

}  // namespace
}  // namespace mgelastic::grid
