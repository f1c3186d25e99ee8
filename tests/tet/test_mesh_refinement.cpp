// Uniform red refinement (mesh_refinement.hpp): 8 children, volume kept, conforming, positive.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>

#include "mgelastic/tet/mesh_refinement.hpp"
#include "tet/tet_test_support.hpp"

namespace mgelastic::tet {
namespace {

double total_volume(const geometry::TetMesh& mesh) {
  double volume = 0.0;
  for (int t = 0; t < mesh.tet_count(); ++t) {
    const Eigen::Matrix<double, 3, 4> c = mesh.corners(t);
    volume += geometry::signed_volume6(c.col(0), c.col(1), c.col(2), c.col(3)) / 6.0;
  }
  return volume;
}

// Faces used by exactly one tetrahedron (the boundary of a conforming mesh).
int boundary_faces(const geometry::TetMesh& mesh) {
  std::map<std::array<int, 3>, int> uses;
  for (int t = 0; t < mesh.tet_count(); ++t)
    for (int skip = 0; skip < 4; ++skip) {
      std::array<int, 3> face;
      int k = 0;
      for (int a = 0; a < 4; ++a)
        if (a != skip) face[k++] = mesh.tets(t, a);
      std::sort(face.begin(), face.end());
      ++uses[face];
    }
  int count = 0;
  for (const auto& [face, n] : uses) {
    EXPECT_LE(n, 2);
    count += n == 1 ? 1 : 0;
  }
  return count;
}

TEST(MeshRefinement, EightChildrenSameVolumeConformingAndPositive) {
  const geometry::TetMesh mesh = test::box_mesh(Eigen::Vector3d(1.0, 0.5, 0.75), 0.25);
  const geometry::TetMesh fine = refine_uniform(mesh);
  ASSERT_EQ(fine.tet_count(), 8 * mesh.tet_count());
  EXPECT_NEAR(total_volume(fine), 1.0 * 0.5 * 0.75, 1e-12);
  // Each boundary triangle splits into four; a crack would add inner boundary faces.
  EXPECT_EQ(boundary_faces(fine), 4 * boundary_faces(mesh));
  for (int t = 0; t < fine.tet_count(); ++t) {
    const Eigen::Matrix<double, 3, 4> c = fine.corners(t);
    EXPECT_GT(geometry::signed_volume6(c.col(0), c.col(1), c.col(2), c.col(3)), 0.0) << t;
  }
  // Parent vertices keep their indices; every new vertex is an edge midpoint (V + E vertices).
  EXPECT_TRUE(fine.vertices.topRows(mesh.vertex_count()).isApprox(mesh.vertices));
}

}  // namespace
}  // namespace mgelastic::tet
