#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "mgelastic/geometry/primitives.hpp"
#include "mgelastic/geometry/voxelization.hpp"

namespace mgelastic::geometry {
namespace {

double occupied_volume(const VoxelGrid& grid) {
  double count = 0;
  for (auto c : grid.occupied) count += c;
  return count * std::pow(grid.cell_size, 3);
}

// The overlap rule over-estimates by about half a boundary layer, so the relative error of the
// voxelized volume shrinks like h: below 15% at 64 cells (12.5% for the thin torus) and about 4x
// smaller than at 16 cells.
TEST(Voxelization, VolumeConvergesToTheAnalyticVolume) {
  const auto sphere = make_sphere(Point::Zero(), 0.5);
  const auto torus = make_torus(Point::Zero(), Point(0, 0, 1), 0.6, 0.25);
  const double pi = std::numbers::pi;
  for (auto [shape, exact] : {std::pair{sphere, 4.0 / 3.0 * pi * 0.125},
                              std::pair{torus, 2 * pi * pi * 0.6 * 0.25 * 0.25}}) {
    std::vector<double> errors;
    for (int resolution : {16, 32, 64}) {
      const VoxelGrid grid = voxelize(*shape, {.resolution = resolution});
      errors.push_back(std::abs(occupied_volume(grid) - exact) / exact);
    }
    EXPECT_LT(errors[2], 0.15);
    EXPECT_LT(errors[2], 0.35 * errors[0]);
    EXPECT_LT(errors[1], errors[0]);
  }
}

TEST(Voxelization, BoxAlignedWithTheGridIsExact) {
  const auto box = make_box(Point(0.5, 0.5, 0.5), Point(1.0, 0.5, 0.25));
  const VoxelGrid grid = voxelize(*box, {.cell_size = 0.125});
  EXPECT_NEAR(occupied_volume(grid), 0.125, 1e-12);  // cells touching only a face don't overlap
}

TEST(Voxelization, PaddingAddsLayersAndMarginStaysEmpty) {
  const auto sphere = make_sphere(Point::Zero(), 0.5);
  const VoxelGrid plain = voxelize(*sphere, {.resolution = 16, .margin = 2});
  const VoxelGrid padded = voxelize(*sphere, {.resolution = 16, .padding = 1, .margin = 2});
  EXPECT_GT(occupied_volume(padded), occupied_volume(plain));
  for (int j = 0; j < padded.dims[1]; ++j)
    for (int i = 0; i < padded.dims[0]; ++i) EXPECT_EQ(padded.occupied[padded.index(i, j, 0)], 0);
}

TEST(Voxelization, RegionsSelectOverlappingCells) {
  const auto body = make_box(Point::Zero(), Point(1, 1, 1));
  const VoxelGrid grid = voxelize(*body, {.resolution = 8});
  const auto slab = make_box(Point(0, -0.5, 0), Point(2, 0.2, 2));
  const auto mask = overlapping_cells(grid, *slab);
  int selected = 0;
  for (std::size_t c = 0; c < mask.size(); ++c) selected += mask[c] && grid.occupied[c];
  EXPECT_EQ(selected, 8 * 8);  // the bottom layer of the body (0.125 thick, slab reaches -0.4)
}

// Two cells touching along an edge, and two touching at a corner, get a face path between them.
TEST(Voxelization, DiagonalContactsAreBridgedIntoFaceConnections) {
  VoxelGrid grid;
  grid.dims = Eigen::Vector3i(4, 4, 4);
  grid.occupied.assign(64, 0);
  grid.occupied[grid.index(0, 0, 0)] = grid.occupied[grid.index(1, 1, 0)] = 1;  // edge contact
  grid.occupied[grid.index(3, 3, 3)] = grid.occupied[grid.index(2, 2, 2)] = 1;  // corner contact
  EXPECT_EQ(bridge_diagonal_contacts(grid), 3);
  // Edge pair: one of the two cells sharing a face with both is now occupied.
  EXPECT_TRUE(grid.occupied[grid.index(1, 0, 0)] || grid.occupied[grid.index(0, 1, 0)]);
  // A second pass finds nothing left to bridge.
  EXPECT_EQ(bridge_diagonal_contacts(grid), 0);
}

}  // namespace
}  // namespace mgelastic::geometry
