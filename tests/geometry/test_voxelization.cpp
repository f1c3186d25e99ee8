#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

#include <filesystem>

#include "geometry/surface_mesh_test_support.hpp"
#include "mgelastic/geometry/csg.hpp"
#include "mgelastic/geometry/mesh_shape.hpp"
#include "mgelastic/geometry/primitives.hpp"
#include "mgelastic/geometry/voxelization.hpp"

namespace mgelastic::geometry {
namespace {

// The occupancy definition of voxelization.hpp, query by query: d(center), then all 4^3 samples.
std::vector<std::uint8_t> reference_overlapping_cells(const VoxelGrid& grid, const Shape& shape) {
  std::vector<std::uint8_t> mask(grid.cell_count(), 0);
  const double h = grid.cell_size;
  for (int k = 0; k < grid.dims[2]; ++k)
    for (int j = 0; j < grid.dims[1]; ++j)
      for (int i = 0; i < grid.dims[0]; ++i) {
        const Point center = grid.cell_center(i, j, k);
        const double d = shape.signed_distance(center);
        bool overlaps = d <= 0.0;
        if (!overlaps && d <= 0.5 * std::sqrt(3.0) * h)
          for (int s = 0; s < 64 && !overlaps; ++s) {
            const Eigen::Vector3d index(s % 4, (s / 4) % 4, s / 16);
            const Point offset = ((index.array() + 0.5) / 4 - 0.5).matrix() * h;
            overlaps = shape.signed_distance(center + offset) <= 0.0;
          }
        mask[grid.index(i, j, k)] = overlaps;
      }
  return mask;
}

// overlapping_cells skips the sample queries whose sign a nearer query already implies; it must
// give the definition's answer cell for cell.
void expect_reference_occupancy(const Shape& shape, int resolution, const std::string& name) {
  VoxelizeOptions options;
  options.resolution = resolution;
  const VoxelLattice lattice = voxel_lattice(shape.bounding_box(), options);
  VoxelGrid grid;
  grid.cell_size = lattice.cell_size;
  grid.dims = lattice.cells.cast<int>();
  grid.origin = lattice.origin;
  const std::vector<std::uint8_t> fast = overlapping_cells(grid, shape);
  const std::vector<std::uint8_t> reference = reference_overlapping_cells(grid, shape);
  std::size_t differ = 0, occupied = 0;
  for (std::size_t c = 0; c < fast.size(); ++c) {
    differ += fast[c] != reference[c];
    occupied += reference[c];
  }
  EXPECT_GT(occupied, 0u) << name;
  EXPECT_EQ(differ, 0u) << name << ": cells that differ from the definition";
}

TEST(Voxelization, SkippedSampleQueriesKeepTheDefinitionsOccupancy) {
  const ShapePtr carved = make_difference({make_box(Point(0.5, 0.5, 0.5), Point(1, 0.8, 0.6)),
                                           make_sphere(Point(0.2, 0.3, 0.7), 0.35)});
  const ShapePtr ring = make_torus(Point(0, 0, 0), Point(0.3, 0.2, 1), 0.6, 0.12);
  for (int n : {13, 24}) {
    expect_reference_occupancy(*carved, n, "box minus sphere at " + std::to_string(n));
    expect_reference_occupancy(*ring, n, "torus at " + std::to_string(n));
  }
  const std::filesystem::path dir = test::data_dir();
  if (dir.empty()) return;
  for (const char* file : {"armadillo.obj", "bunny.off", "spot.obj"}) {
    ASSERT_TRUE(std::filesystem::exists(dir / file)) << dir / file << " is missing";
    expect_reference_occupancy(*load_mesh_shape(dir / file), 24, file);
  }
}

// A closed mesh's cells off its surface take the side of their piece of space, one winding
// number query per piece (Shape::closed_surface); the occupancy is still the definition's.
// Large triangles whose bounding boxes span the lattice (a rotated box of 12 triangles), a
// torus-like cavity (a box inside a box, inside-out: two pieces inside), small triangles of the
// shared meshes at a finer lattice than above; a mesh with a hole keeps the distance walk.
TEST(Voxelization, ClosedMeshesDecideCellsOffTheSurfaceByPiece) {
  TriangleMesh rotated = test::make_box_mesh(Point(-0.5, -0.3, -0.2), Point(0.5, 0.3, 0.2), 1);
  const Eigen::Matrix3d turn =
      (Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized())).toRotationMatrix();
  rotated.vertices = rotated.vertices * turn.transpose();
  const ShapePtr box = make_mesh_shape(rotated, "rotated box");
  ASSERT_NE(box->closed_surface(), nullptr);
  EXPECT_EQ(box->closed_surface()->size(), 12u);
  for (int n : {17, 40}) expect_reference_occupancy(*box, n, "rotated box at " + std::to_string(n));

  // A hollow box: the outer surface, and an inner one facing inwards (the cavity is outside).
  TriangleMesh outer = test::make_box_mesh(Point(0, 0, 0), Point(1, 1, 1), 2);
  TriangleMesh inner = test::make_box_mesh(Point(0.3, 0.3, 0.3), Point(0.7, 0.7, 0.7), 2);
  const Eigen::Index offset = outer.vertices.rows();
  TriangleMesh hollow;
  hollow.vertices.resize(offset + inner.vertices.rows(), 3);
  hollow.vertices << outer.vertices, inner.vertices;
  hollow.triangles.resize(outer.triangles.rows() + inner.triangles.rows(), 3);
  hollow.triangles << outer.triangles, inner.triangles.rowwise().reverse().array() + offset;
  const ShapePtr shell = make_mesh_shape(hollow, "hollow box");
  ASSERT_NE(shell->closed_surface(), nullptr);
  expect_reference_occupancy(*shell, 23, "hollow box");

  const ShapePtr open =
      make_mesh_shape(test::remove_triangles(test::make_icosphere(3), {5}), "sphere with a hole");
  EXPECT_EQ(open->closed_surface(), nullptr);
  expect_reference_occupancy(*open, 20, "sphere with a hole");

  const std::filesystem::path dir = test::data_dir();
  if (dir.empty()) return;
  for (const char* file : {"armadillo.obj", "bunny.off"}) {
    ASSERT_TRUE(std::filesystem::exists(dir / file)) << dir / file << " is missing";
    const ShapePtr mesh = load_mesh_shape(dir / file);
    ASSERT_NE(mesh->closed_surface(), nullptr) << file;
    expect_reference_occupancy(*mesh, 40, file);
  }
}

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
  // Two cells thick: without thin-feature thickening (min_thickness = 2) the set is the box.
  const VoxelGrid grid = voxelize(*box, {.cell_size = 0.125, .min_thickness = 2});
  EXPECT_NEAR(occupied_volume(grid), 0.125, 1e-12);  // cells touching only a face don't overlap
}

// By default a feature thinner than three cells gets a third layer (the first coarse level then
// has no one-cell sheets); thicker bodies are left as they are.
TEST(Voxelization, ThinFeaturesAreThickenedToThreeCells) {
  const auto slab = make_box(Point(0.5, 0.5, 0.5), Point(1.0, 0.5, 0.25));
  EXPECT_NEAR(occupied_volume(voxelize(*slab, {.cell_size = 0.125})), 0.1875, 1e-12);
  const auto block = make_box(Point(0.5, 0.5, 0.5), Point(1.0, 0.5, 0.375));
  EXPECT_NEAR(occupied_volume(voxelize(*block, {.cell_size = 0.125})), 0.1875, 1e-12);
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

VoxelGrid boxes(const Eigen::Vector3i& dims,
                const std::vector<std::pair<Eigen::Vector3i, Eigen::Vector3i>>& ranges) {
  VoxelGrid grid;
  grid.dims = dims;
  grid.occupied.assign(static_cast<std::size_t>(dims.prod()), 0);
  for (const auto& [lo, hi] : ranges)
    for (int k = lo[2]; k < hi[2]; ++k)
      for (int j = lo[1]; j < hi[1]; ++j)
        for (int i = lo[0]; i < hi[0]; ++i) grid.occupied[grid.index(i, j, k)] = 1;
  return grid;
}

int occupied_count(const VoxelGrid& grid) {
  int count = 0;
  for (auto c : grid.occupied) count += c;
  return count;
}

// Two 4^3 cubes touching through a single cell face, or through a strip one cell wide, are
// hinged (grid tests: Coarsening.HingedPartsMakeTheLatticeSingular). The repair chains their
// full 2x2x2 blocks with a few cells, keeps every cell it had, and is then idempotent.
TEST(Voxelization, HingesAreChainedIntoOneRigidUnionOfBlocks) {
  using V = Eigen::Vector3i;
  for (bool strip : {false, true}) {
    SCOPED_TRACE(strip ? "strip hinge" : "single-face hinge");
    const V b(5, strip ? 1 : 4, 4);
    VoxelGrid grid = boxes(V(11, 10, 10), {{V(1, 1, 1), V(5, 5, 5)}, {b, b + V(4, 4, 4)}});
    const VoxelGrid before = grid;
    const int added = connect_thick_blocks(grid);
    EXPECT_GT(added, 0);
    EXPECT_LE(added, 8);
    EXPECT_EQ(occupied_count(grid), occupied_count(before) + added);
    int lost = 0;
    for (std::size_t c = 0; c < grid.occupied.size(); ++c)
      lost += before.occupied[c] && !grid.occupied[c];
    EXPECT_EQ(lost, 0);
    EXPECT_EQ(connect_thick_blocks(grid), 0);
  }
}

// Blocks that already share 2x2 halves, and separate pieces, are left alone.
TEST(Voxelization, RigidAndSeparatePiecesAreNotConnected) {
  using V = Eigen::Vector3i;
  VoxelGrid l_shape = boxes(V(10, 10, 6), {{V(1, 1, 1), V(8, 3, 3)}, {V(1, 1, 1), V(3, 8, 3)}});
  EXPECT_EQ(connect_thick_blocks(l_shape), 0);
  VoxelGrid apart = boxes(V(12, 6, 6), {{V(1, 1, 1), V(5, 5, 5)}, {V(6, 1, 1), V(10, 5, 5)}});
  EXPECT_EQ(connect_thick_blocks(apart), 0);
}

// Every cell of a thickened set lies in a full 2x2x2 block (a one-cell sheet gets a second
// layer), and thickening again adds nothing.
TEST(Voxelization, ThickeningPutsEveryCellInAFullBlock) {
  using V = Eigen::Vector3i;
  VoxelGrid sheet = boxes(V(8, 8, 5), {{V(1, 1, 2), V(7, 7, 3)}});
  EXPECT_EQ(thicken_thin_features(sheet), 36);
  EXPECT_EQ(thicken_thin_features(sheet), 0);
}

}  // namespace
}  // namespace mgelastic::geometry
