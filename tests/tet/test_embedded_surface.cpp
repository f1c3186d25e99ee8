#include "mgelastic/tet/embedded_surface.hpp"

#include <gtest/gtest.h>

#include <random>

#include "mgelastic/core/error.hpp"
#include "mgelastic/geometry/marching_cubes.hpp"
#include "mgelastic/geometry/primitives.hpp"
#include "mgelastic/geometry/tet_mesh_boundary.hpp"
#include "tet_test_support.hpp"

namespace mgelastic::tet {
namespace {

// Interpolation of O(1) coordinates with O(1) weights: a few ulps.
constexpr double kRest = 1e-12;
// Extrapolation with weights of magnitude up to ~10 (vertices a cube or so outside their tet).
constexpr double kAffine = 1e-10;

// Points inside the box mesh: random, plus grid vertices, edge midpoints and face centers, which
// lie on faces shared by several tets.
geometry::TriangleMesh points_inside(const Eigen::Vector3d& size, double h) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Eigen::Vector3d> points;
  for (int n = 0; n < 500; ++n)
    points.push_back(Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).cwiseProduct(size));
  for (double x = 0; x <= size[0] + 1e-9; x += 0.5 * h)
    for (double y = 0; y <= size[1] + 1e-9; y += 0.5 * h)
      for (double z = 0; z <= size[2] + 1e-9; z += 0.5 * h) points.emplace_back(x, y, z);
  geometry::TriangleMesh surface;
  surface.vertices.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i)
    surface.vertices.row(static_cast<Eigen::Index>(i)) = points[i].transpose();
  return surface;
}

TEST(EmbeddedSurface, PointsInsideGetBarycentricsOfTheirTet) {
  const Eigen::Vector3d size(1.0, 0.6, 0.4);
  const double h = 0.2;
  const geometry::TetMesh mesh = test::box_mesh(size, h);
  const geometry::TriangleMesh surface = points_inside(size, h);
  const EmbeddedSurface embedded = embed_surface(mesh, surface);
  ASSERT_EQ(embedded.vertex_count(), surface.vertex_count());
  EXPECT_EQ(embedded.outside_vertices, 0);
  for (Eigen::Index s = 0; s < embedded.vertex_count(); ++s) {
    EXPECT_GE(embedded.weights.row(s).minCoeff(), -1e-12) << "vertex " << s;
    EXPECT_NEAR(embedded.weights.row(s).sum(), 1.0, 1e-12) << "vertex " << s;
  }
  const SurfacePoints rest = embedded_positions(embedded, mesh.vertices, mesh.tets);
  EXPECT_LE((rest - surface.vertices).cwiseAbs().maxCoeff(), kRest);
}

// A sphere of radius 1 meshed by cubes of edge 0.5 whose centers are inside: the tets miss the
// sphere's outer shell, so a large part of the surface (44 %) lies outside every tet.
struct CoarseSphere {
  geometry::TetMesh mesh;
  geometry::TriangleMesh surface;
  CoarseSphere() {
    const geometry::ShapePtr sphere = geometry::make_sphere(Eigen::Vector3d::Zero(), 1.0);
    mesh = geometry::regular_tet_grid(
               [&](const Eigen::Vector3d& p) { return sphere->contains(p); },
               Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-1.0), Eigen::Vector3d::Constant(1.0)),
               0.5)
               .mesh;
    surface = geometry::extract_surface(*sphere, 0.1);
  }
};

TEST(EmbeddedSurface, VerticesOutsideTheGridReproduceTheirRestPosition) {
  const CoarseSphere sphere;
  const EmbeddedSurface embedded = embed_surface(sphere.mesh, sphere.surface);
  EXPECT_GT(embedded.outside_vertices, embedded.vertex_count() / 4);  // 44 %
  EXPECT_GT(embedded.max_outside_distance, 0.0);
  EXPECT_LT(embedded.max_outside_distance, 0.5);  // within a cube of the grid
  for (Eigen::Index s = 0; s < embedded.vertex_count(); ++s)
    EXPECT_NEAR(embedded.weights.row(s).sum(), 1.0, 1e-12) << "vertex " << s;
  const SurfacePoints rest = embedded_positions(embedded, sphere.mesh.vertices, sphere.mesh.tets);
  EXPECT_LE((rest - sphere.surface.vertices).cwiseAbs().maxCoeff(), kRest);
}

TEST(EmbeddedSurface, VerticesOutsideTheGridMoveAffinely) {
  const CoarseSphere sphere;
  const EmbeddedSurface embedded = embed_surface(sphere.mesh, sphere.surface);
  Eigen::Matrix3d a;
  a << 1.3, 0.2, -0.1, 0.05, 0.8, 0.3, -0.2, 0.1, 1.1;
  const Eigen::RowVector3d t(0.4, -1.2, 2.5);
  const auto affine = [&](const auto& x) {
    return Eigen::MatrixX3d((x * a.transpose()).rowwise() + t);
  };
  const SurfacePoints moved =
      embedded_positions(embedded, affine(sphere.mesh.vertices), sphere.mesh.tets);
  EXPECT_LE((moved - affine(sphere.surface.vertices)).cwiseAbs().maxCoeff(), kAffine);
}

TEST(EmbeddedSurface, FarPointsBindToTheNearestTet) {
  const geometry::TetMesh mesh = test::box_mesh(Eigen::Vector3d::Ones(), 0.25);
  geometry::TriangleMesh surface;
  surface.vertices.resize(2, 3);
  surface.vertices << 3.0, 0.5, 0.5,  // nearest: the face x = 1
      -0.3, -0.2, 1.4;                // nearest: the corner (0, 0, 1)
  const EmbeddedSurface embedded = embed_surface(mesh, surface);
  EXPECT_EQ(embedded.outside_vertices, 2);
  EXPECT_NEAR(embedded.max_outside_distance, 2.0, 1e-12);
  for (int s = 0; s < 2; ++s) {
    const Eigen::Matrix<double, 3, 4> c = mesh.corners(embedded.tet[s]);
    const Eigen::Vector3d near = s == 0 ? Eigen::Vector3d(1.0, 0.5, 0.5) : Eigen::Vector3d(0, 0, 1);
    const double gap = (c.colwise() - near).colwise().norm().minCoeff();
    if (s == 1) {
      EXPECT_NEAR(gap, 0.0, 1e-12);  // the corner is one of the tet's vertices
    }
    EXPECT_LE((c.rowwise().minCoeff() - near).maxCoeff(), 1e-12);  // the tet touches `near`
    EXPECT_LE((near - c.rowwise().maxCoeff()).maxCoeff(), 1e-12);
  }
}

TEST(EmbeddedSurface, BoundaryAsEmbeddedReturnsTheBoundaryVertices) {
  const geometry::TetMesh mesh = test::box_mesh(Eigen::Vector3d(1.0, 0.5, 0.5), 0.25);
  const geometry::TetMeshBoundary boundary = geometry::tet_mesh_boundary(mesh);
  const EmbeddedSurface embedded = boundary_as_embedded(mesh, boundary);
  const Eigen::MatrixX3d moved = mesh.vertices * 2.0;
  const SurfacePoints y = embedded_positions(embedded, moved, mesh.tets);
  for (std::size_t s = 0; s < boundary.mesh_vertex.size(); ++s)
    EXPECT_TRUE(y.row(static_cast<Eigen::Index>(s)) == moved.row(boundary.mesh_vertex[s])) << s;
  EXPECT_TRUE(embedded.triangles == boundary.triangles);
}

TEST(EmbeddedSurface, EmptyMeshIsAnError) {
  EXPECT_THROW(embed_surface(geometry::TetMesh{}, geometry::TriangleMesh{}), Error);
}

}  // namespace
}  // namespace mgelastic::tet
