#pragma once
// How many lattice points each storage layout would keep per active cell: the measurement behind
// issue 24's block-sparse tiles (item 4), taken before building them.
//
// Every level stores its fields over the padded bounding box (lattice.hpp). An embedded body
// needs only the points where some field has a variable (not INACTIVE), plus what the kernels
// read around them. The census counts, over all levels of a hierarchy, against the finest
// level's active (INTERIOR) cells:
//   bounding_box      lattice.size(): the dense layout of today;
//   with_variables    points where some field has a variable: no layout keeps fewer;
//   live_pages        points in the 4 KiB pages of a float array (1024 consecutive flat indices)
//                     that hold a variable: the best that releasing pages of the row-major
//                     layout can reach (live_chunks.hpp keeps more: whole neighbour rows, and
//                     huge pages);
//   row_ranges        points of one x-range per storage row, from its first to its last point
//                     that holds a variable or a stencil neighbour of one: a row-compressed
//                     layout (a row table of base offsets, rows contiguous along x);
//   tiles (a, b, c)   points in a x b x c tiles (x fastest) that hold a variable or a stencil
//                     neighbour of one (the 27 points around it): a tile-major layout where a
//                     kernel finds every neighbour it reads in an allocated tile.
// Over all levels (docs/performance.md): the 128^3 mixed box keeps 1.38 points per active cell
// densely (padding ring, Dirichlet slab, coarse levels), 1.45 / 1.62 / 1.88 in 4^3 / 8^3 /
// 32 x 8 x 4 tiles (its rows do not divide into tiles) and 1.38 in row ranges; the armadillo
// at 256 cells 10.02 densely, 1.86 with variables (its surface faces live at the exterior
// cells next to it), 5.10 in 4 KiB pages, 2.56 in row ranges, 2.49 / 3.05 / 3.59 in those
// tiles; the bunny at 256 cells 4.62, 1.47, 3.08, 1.61 (row ranges), 1.74 / 1.96 / 2.23.
#include <array>
#include <cstddef>
#include <vector>

#include "mgelastic/grid/level.hpp"

namespace mgelastic::grid {

struct TileCensus {
  std::array<int, 3> size{};  // cells per tile along x, y, z (z ignored in 2D)
  std::size_t tiles = 0;      // tiles allocated
  std::size_t points = 0;     // tiles * points per tile
};

struct LayoutCensus {
  std::size_t active_cells = 0;  // INTERIOR cells of the finest level
  std::size_t bounding_box = 0, with_variables = 0, live_pages = 0;
  std::size_t row_ranges = 0;     // one x-range per storage row
  std::vector<TileCensus> tiles;  // one per requested tile size
};

// The census of one level.
template <int Dim, typename Scalar>
LayoutCensus layout_census(const Level<Dim, Scalar>& level,
                           const std::vector<std::array<int, 3>>& tile_sizes);

// Sums of the levels' censuses (points), with the finest level's active cells.
template <int Dim, typename Scalar>
LayoutCensus layout_census(const std::vector<const Level<Dim, Scalar>*>& levels,
                           const std::vector<std::array<int, 3>>& tile_sizes);

}  // namespace mgelastic::grid
