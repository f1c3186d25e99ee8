// Regular tetrahedral grid (Kuhn split) and the VTU writer.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <fstream>
#include <map>
#include <sstream>

#include "mgelastic/core/error.hpp"
#include "mgelastic/geometry/tet_mesh_grid.hpp"
#include "mgelastic/geometry/tet_mesh_vtu.hpp"
#include "tet/tet_test_support.hpp"

namespace mgelastic::geometry {
namespace {

TEST(RegularTetGrid, BoxIsConformingAndPositivelyOriented) {
  const int nx = 3, ny = 2, nz = 2;
  const TetMesh mesh = test::box_mesh(Eigen::Vector3d(nx, ny, nz), 1.0);
  ASSERT_EQ(mesh.tet_count(), 6 * nx * ny * nz);
  ASSERT_EQ(mesh.vertex_count(), (nx + 1) * (ny + 1) * (nz + 1));
  double volume = 0.0;
  std::map<std::array<int, 3>, int> faces;
  for (int t = 0; t < mesh.tet_count(); ++t) {
    const auto c = mesh.corners(t);
    const double v6 = signed_volume6(c.col(0), c.col(1), c.col(2), c.col(3));
    ASSERT_GT(v6, 0.0);
    volume += v6 / 6.0;
    for (int skip = 0; skip < 4; ++skip) {
      std::array<int, 3> face;
      for (int a = 0, k = 0; a < 4; ++a)
        if (a != skip) face[k++] = mesh.tets(t, a);
      std::sort(face.begin(), face.end());
      ++faces[face];
    }
  }
  EXPECT_NEAR(volume, nx * ny * nz, 1e-12);
  // Conforming: every face is shared by two tets, except the two triangles per boundary square.
  int boundary = 0;
  for (const auto& [face, count] : faces) {
    ASSERT_LE(count, 2);
    boundary += count == 1 ? 1 : 0;
  }
  EXPECT_EQ(boundary, 2 * 2 * (nx * ny + ny * nz + nx * nz));
}

TEST(RegularTetGrid, SphereKeepsOnlyUsedVertices) {
  const auto inside = [](const Eigen::Vector3d& p) { return p.norm() < 1.0; };
  const Eigen::AlignedBox3d box(Eigen::Vector3d::Constant(-1), Eigen::Vector3d::Constant(1));
  const RegularTetGrid center = regular_tet_grid(inside, box, 0.2, CubeSelection::CENTER);
  const RegularTetGrid corner = regular_tet_grid(inside, box, 0.2, CubeSelection::ANY_CORNER);
  EXPECT_EQ(center.cells, Eigen::Vector3i(10, 10, 10));
  EXPECT_LT(center.mesh.tet_count(), corner.mesh.tet_count());
  std::vector<int> used(center.mesh.vertex_count(), 0);
  for (int t = 0; t < center.mesh.tet_count(); ++t)
    for (int a = 0; a < 4; ++a) used[center.mesh.tets(t, a)] = 1;
  EXPECT_EQ(std::count(used.begin(), used.end(), 1), center.mesh.vertex_count());
  for (int v = 0; v < center.mesh.vertex_count(); ++v)
    EXPECT_LE(
        (center.mesh.vertices.row(v) -
         (box.min() + 0.2 * center.vertex_grid_index.row(v).cast<double>().transpose()).transpose())
            .norm(),
        1e-12);
}

TEST(RegularTetGrid, InvalidArgumentsThrow) {
  const auto all = [](const Eigen::Vector3d&) { return true; };
  const auto none = [](const Eigen::Vector3d&) { return false; };
  const Eigen::AlignedBox3d box(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones());
  EXPECT_THROW(regular_tet_grid(all, box, 0.0), Error);
  EXPECT_THROW(regular_tet_grid(all, box, 1e-4), Error);  // 1e12 grid points
  EXPECT_THROW(regular_tet_grid(none, box, 0.5), Error);
  EXPECT_THROW(regular_tet_grid(all, Eigen::AlignedBox3d(), 0.5), Error);
}

TEST(WriteVtu, WritesFieldsAtomically) {
  test::TempDir dir;
  TetMesh mesh = test::box_mesh(Eigen::Vector3d(1, 1, 1), 0.5);
  mesh.element_tags = Eigen::VectorXi::Constant(mesh.tet_count(), 3);
  const VtuField displacement{"displacement", Eigen::MatrixXd::Ones(mesh.vertex_count(), 3)};
  const VtuField stress{"stress", Eigen::MatrixXd::Zero(mesh.tet_count(), 1)};
  const auto path = dir.path() / "frame.vtu";
  write_vtu(path, mesh, std::span(&displacement, 1), std::span(&stress, 1));
  EXPECT_FALSE(std::filesystem::exists(path.string() + ".tmp"));
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  for (const std::string expected :
       {"NumberOfPoints=\"27\"", "NumberOfCells=\"48\"", "Name=\"displacement\"", "Name=\"stress\"",
        "Name=\"tag\"", "</VTKFile>"})
    EXPECT_NE(text.str().find(expected), std::string::npos) << expected;
}

TEST(WriteVtu, MismatchedFieldThrowsAndLeavesNoFile) {
  test::TempDir dir;
  const TetMesh mesh = test::box_mesh(Eigen::Vector3d(1, 1, 1), 0.5);
  const VtuField wrong{"wrong", Eigen::MatrixXd::Ones(3, 3)};
  const auto path = dir.path() / "frame.vtu";
  EXPECT_THROW(write_vtu(path, mesh, std::span(&wrong, 1)), Error);
  EXPECT_FALSE(std::filesystem::exists(path));
  EXPECT_FALSE(std::filesystem::exists(path.string() + ".tmp"));
}

}  // namespace
}  // namespace mgelastic::geometry
