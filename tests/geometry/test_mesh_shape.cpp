#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <iostream>
#include <numbers>
#include <random>

#include "geometry/surface_mesh_test_support.hpp"
#include "mgelastic/core/error.hpp"
#include "mgelastic/geometry/mesh_shape.hpp"
#include "mgelastic/geometry/primitives.hpp"
#include "mgelastic/geometry/surface_mesh_readers.hpp"
#include "mgelastic/geometry/winding_number.hpp"
#include "mgelastic/io/surface_mesh_writers.hpp"

namespace mgelastic::geometry {
namespace {

using test::make_box_mesh;
using test::make_icosphere;
using test::random_point;

// Distances to a mesh of exactly representable planes are exact up to a few ulps.
constexpr double kExactDistance = 1e-12;

std::string rejection_of(TriangleMesh mesh, const std::string& source) {
  try {
    make_mesh_shape(std::move(mesh), source);
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << source << " was accepted";
  return {};
}

const MeshShape& as_mesh(const ShapePtr& shape) {
  return dynamic_cast<const MeshShape&>(*shape);
}

TEST(MeshFacts, ClosedIcosphereAndBox) {
  const MeshFacts sphere = mesh_facts(make_icosphere(3));
  EXPECT_TRUE(sphere.closed && sphere.manifold && sphere.consistently_oriented);
  EXPECT_EQ(sphere.components, 1);
  EXPECT_EQ(sphere.degenerate_triangles, 0);
  EXPECT_EQ(sphere.triangle_count, 1280);
  EXPECT_NEAR(sphere.signed_volume, 4.0 / 3.0 * std::numbers::pi, 0.05);  // inscribed: smaller
  EXPECT_LT(sphere.signed_volume, 4.0 / 3.0 * std::numbers::pi);
  const MeshFacts box = mesh_facts(make_box_mesh(Point(0, 0, 0), Point(1, 2, 3), 3));
  EXPECT_TRUE(box.closed && box.manifold && box.consistently_oriented);
  EXPECT_NEAR(box.signed_volume, 6.0, 1e-12);
  EXPECT_TRUE(box.bounding_box.isApprox(BoundingBox(Point(0, 0, 0), Point(1, 2, 3))));
}

// Defects are counted, not fatal: a collapsed triangle, a flipped one, two components.
TEST(MeshFacts, DefectsAreCounted) {
  TriangleMesh mesh = make_box_mesh(Point(0, 0, 0), Point(1, 1, 1), 1);
  std::swap(mesh.triangles(0, 1), mesh.triangles(0, 2));  // one misoriented triangle
  const TriangleMesh other = make_box_mesh(Point(3, 0, 0), Point(4, 1, 1), 1);
  const Eigen::Index n = mesh.vertex_count(), t = mesh.triangle_count();
  mesh.vertices.conservativeResize(n + other.vertex_count(), 3);
  mesh.vertices.bottomRows(other.vertex_count()) = other.vertices;
  mesh.triangles.conservativeResize(t + other.triangle_count() + 1, 3);
  mesh.triangles.middleRows(t, other.triangle_count()) = other.triangles.array() + int(n);
  mesh.triangles.bottomRows(1) << 0, 0, 1;  // collapsed: no edges of its own
  const MeshFacts facts = mesh_facts(mesh);
  EXPECT_EQ(facts.components, 2);
  EXPECT_EQ(facts.degenerate_triangles, 1);
  EXPECT_EQ(facts.inconsistent_edges, 3);
  EXPECT_FALSE(facts.consistently_oriented);
  EXPECT_TRUE(facts.closed && facts.manifold);
}

TEST(MeshShape, ContainsMatchesTheAnalyticSphereAndBox) {
  const ShapePtr sphere = make_mesh_shape(make_icosphere(4, 0.8, Point(0.1, 0, 0)), "sphere");
  const ShapePtr box =
      make_mesh_shape(make_box_mesh(Point(-0.5, -0.3, -0.2), Point(0.7, 0.3, 0.2), 4), "box");
  const auto analytic_box = make_box(Point(0.1, 0, 0), Point(1.2, 0.6, 0.4));
  std::mt19937 rng(11);
  for (int n = 0; n < 2000; ++n) {
    const Point p = random_point(rng, 1.2);
    const double r = (p - Point(0.1, 0, 0)).norm();
    if (std::abs(r - 0.8) > 0.01) {
      EXPECT_EQ(sphere->contains(p), r < 0.8) << p;
    }
    if (std::abs(analytic_box->signed_distance(p)) > 1e-3) {
      EXPECT_EQ(box->contains(p), analytic_box->contains(p)) << p;
    }
  }
}

// The mesh of a box has the box's exact signed distance (inside and outside, corners included).
TEST(MeshShape, SignedDistanceOfABoxIsExact) {
  const ShapePtr box = make_mesh_shape(make_box_mesh(Point(0, 0, 0), Point(1, 1, 1), 2), "box");
  const auto analytic = make_box(Point(0.5, 0.5, 0.5), Point(1, 1, 1));
  std::mt19937 rng(12);
  for (int n = 0; n < 1000; ++n) {
    const Point p = random_point(rng, 2.0);
    EXPECT_NEAR(box->signed_distance(p), analytic->signed_distance(p), kExactDistance) << p;
  }
}

// A fine icosphere's signed distance approximates the sphere's to within its chordal deviation.
TEST(MeshShape, SignedDistanceApproximatesTheSphere) {
  const ShapePtr sphere = make_mesh_shape(make_icosphere(4), "sphere");
  std::mt19937 rng(13);
  for (int n = 0; n < 1000; ++n) {
    const Point p = random_point(rng, 1.5);
    EXPECT_NEAR(sphere->signed_distance(p), p.norm() - 1.0, test::kIcosphere4Deviation) << p;
  }
  EXPECT_TRUE(sphere->bounding_box().isApprox(BoundingBox(-Point::Ones(), Point::Ones()), 1e-12));
}

// Small holes: accepted, reported by facts, and still classified away from the surface.
TEST(MeshShape, MeshWithHolesIsClassifiedAndReported) {
  const ShapePtr shape =
      make_mesh_shape(test::remove_triangles(make_icosphere(3), {0, 100, 700}), "holes");
  const MeshFacts& facts = as_mesh(shape).facts();
  EXPECT_EQ(facts.boundary_edges, 9);  // three separate triangles removed: three edges each
  EXPECT_FALSE(facts.closed);
  std::mt19937 rng(14);
  for (int n = 0; n < 1000; ++n) {
    const Point p = random_point(rng, 1.5);
    if (std::abs(p.norm() - 1.0) > 0.1) {
      EXPECT_EQ(shape->contains(p), p.norm() < 1.0) << p;
    }
  }
}

// signed_distance_near gives signed_distance's value. On a closed mesh it may take the side of
// the neighbor; next to a hole w changes through the hole, so there it may not: points just
// outside and just inside a removed triangle are on different sides (w ~ 0.35 / 0.65) while
// their surface-free balls overlap through the hole.
TEST(MeshShape, SignedDistanceNearEqualsSignedDistance) {
  const TriangleMesh closed = make_icosphere(3);
  const ShapePtr sphere = make_mesh_shape(closed, "sphere");
  std::mt19937 rng(21);
  for (int n = 0; n < 4000; ++n) {
    const Point q = random_point(rng, 1.3);
    const Point p = q + random_point(rng, 0.1);
    EXPECT_EQ(sphere->signed_distance_near(p, q, sphere->signed_distance(q)),
              sphere->signed_distance(p))
        << p << " near " << q;
  }
  const ShapePtr holed = make_mesh_shape(test::remove_triangles(closed, {0}), "hole");
  const Eigen::Vector3i t = closed.triangles.row(0).transpose();
  const Point a = closed.vertices.row(t[0]), b = closed.vertices.row(t[1]),
              c = closed.vertices.row(t[2]);
  const Point center = (a + b + c) / 3.0;
  const Point normal = (b - a).cross(c - a).normalized();  // outward (icospheres are)
  const double size = (b - a).norm();
  const Point outside = center + 0.2 * size * normal, inside = center - 0.2 * size * normal;
  ASSERT_FALSE(holed->contains(outside));
  ASSERT_TRUE(holed->contains(inside));
  const double d_out = holed->signed_distance(outside), d_in = holed->signed_distance(inside);
  ASSERT_LT((outside - inside).norm(), std::abs(d_out) + std::abs(d_in));  // the balls overlap
  EXPECT_EQ(holed->signed_distance_near(outside, inside, d_in), d_out);
  EXPECT_EQ(holed->signed_distance_near(inside, outside, d_out), d_in);
}

// Non-manifold edges: two boxes sharing an edge, welded by an STL round-trip. Accepted, reported.
TEST(MeshShape, NonManifoldEdgesAreAcceptedAndReported) {
  const TriangleMesh a = make_box_mesh(Point(0, 0, 0), Point(1, 1, 1), 2);
  const TriangleMesh b = make_box_mesh(Point(1, 1, 0), Point(2, 2, 1), 2);
  TriangleMesh both;
  both.vertices.resize(a.vertex_count() + b.vertex_count(), 3);
  both.vertices << a.vertices, b.vertices;
  both.triangles.resize(a.triangle_count() + b.triangle_count(), 3);
  both.triangles << a.triangles, (b.triangles.array() + int(a.vertex_count())).matrix();
  test::SurfaceTempDir dir;
  io::write_stl_binary(dir.path() / "two.stl", both.vertices, both.triangles);
  const ShapePtr shape = load_mesh_shape(dir.path() / "two.stl");
  const MeshFacts& facts = as_mesh(shape).facts();
  EXPECT_EQ(facts.non_manifold_edges, 2);  // the shared edge, split in two segments
  EXPECT_FALSE(facts.manifold);
  EXPECT_EQ(facts.components, 1);
  EXPECT_NEAR(facts.signed_volume, 2.0, 1e-12);
  EXPECT_TRUE(shape->contains(Point(0.5, 0.5, 0.5)));
  EXPECT_TRUE(shape->contains(Point(1.5, 1.5, 0.5)));
  EXPECT_FALSE(shape->contains(Point(1.5, 0.5, 0.5)));
}

// An inside-out mesh is flipped, flagged, and then classifies like the original.
TEST(MeshShape, InsideOutMeshIsFlipped) {
  TriangleMesh mesh = make_icosphere(3);
  flip_orientation(mesh);
  EXPECT_LT(mesh_facts(mesh).signed_volume, 0.0);
  const ShapePtr shape = make_mesh_shape(mesh, "inverted");
  EXPECT_TRUE(as_mesh(shape).inside_out_flipped());
  EXPECT_GT(as_mesh(shape).facts().signed_volume, 0.0);
  EXPECT_TRUE(shape->contains(Point(0, 0, 0)));
  EXPECT_FALSE(shape->contains(Point(1.2, 0, 0)));
  EXPECT_LT(shape->signed_distance(Point(0, 0, 0)), -0.9);
  EXPECT_FALSE(as_mesh(make_mesh_shape(make_icosphere(3), "outward")).inside_out_flipped());
}

TEST(MeshShape, SingleTriangleIsRejected) {
  TriangleMesh mesh;
  mesh.vertices = Eigen::Matrix3d::Identity();
  mesh.triangles.resize(1, 3);
  mesh.triangles << 0, 1, 2;
  const std::string message = rejection_of(mesh, "triangle.obj");
  EXPECT_NE(message.find("triangle.obj: "), std::string::npos) << message;
  EXPECT_NE(message.find("inside and outside are undefined"), std::string::npos) << message;
}

TEST(MeshShape, FlatSheetIsRejected) {
  TriangleMesh sheet = make_box_mesh(Point(0, 0, 0), Point(1, 1, 1), 4);
  sheet.vertices.col(2).setZero();  // squash the box: two coincident sheets, no volume
  const std::string message = rejection_of(sheet, "sheet.stl");
  EXPECT_NE(message.find("sheet.stl: "), std::string::npos) << message;
  EXPECT_NE(message.find("encloses no volume"), std::string::npos) << message;
}

// An open bowl (the upper half of a sphere) has no inside.
TEST(MeshShape, HemisphereIsRejected) {
  const TriangleMesh sphere = make_icosphere(3);
  std::vector<int> lower;
  for (int t = 0; t < sphere.triangle_count(); ++t)
    if (sphere.vertices(sphere.triangles(t, 0), 2) + sphere.vertices(sphere.triangles(t, 1), 2) +
            sphere.vertices(sphere.triangles(t, 2), 2) <
        0)
      lower.push_back(t);
  const std::string message = rejection_of(test::remove_triangles(sphere, lower), "bowl.ply");
  EXPECT_NE(message.find("bowl.ply: "), std::string::npos) << message;
  EXPECT_NE(message.find("boundary edges"), std::string::npos) << message;
}

TEST(MeshShape, EmptyAndInvalidMeshesAreRejected) {
  EXPECT_NE(rejection_of(TriangleMesh(), "empty.obj").find("no triangles"), std::string::npos);
  TriangleMesh bad = make_icosphere(1);
  bad.triangles(7, 2) = 1000;
  const std::string message = rejection_of(bad, "bad.obj");
  EXPECT_NE(message.find("bad.obj: triangle 7"), std::string::npos) << message;
}

// The real models (MGELASTIC_DATA_DIR): read, closed, manifold, outward, accepted; the
// hierarchical winding number matches the exact sum and its speed is reported.
TEST(MeshShape, RealMeshes) {
  const std::filesystem::path dir = test::data_dir();
  if (dir.empty()) GTEST_SKIP() << "MGELASTIC_DATA_DIR is not set";
  for (const std::string name : {"bunny_10k.obj", "bunny.off", "armadillo.obj", "spot.obj"}) {
    const auto path = dir / name;
    ASSERT_TRUE(std::filesystem::exists(path)) << path << " is missing";
    const TriangleMesh mesh = read_surface_mesh(path);
    const MeshFacts facts = mesh_facts(mesh);
    EXPECT_TRUE(facts.closed && facts.manifold && facts.consistently_oriented) << name;
    EXPECT_GT(facts.signed_volume, 0.0) << name;
    const ShapePtr shape = make_mesh_shape(mesh, path.string());
    EXPECT_FALSE(as_mesh(shape).inside_out_flipped()) << name;
    // Compare with the exact sum at points of the bounding box (O(T) each: keep them few).
    const BoundingBox box = shape->bounding_box();
    std::mt19937 rng(15);
    std::vector<Point> points(1000);
    for (auto& p : points)
      p = box.center() + 0.6 * box.sizes().cwiseProduct(random_point(rng, 1.0));
    const MeshShape& mesh_shape = as_mesh(shape);
    double mean = 0.0;
    for (int n = 0; n < 20; ++n) {
      const double error =
          std::abs(mesh_shape.winding_number(points[n]) - exact_winding_number(mesh, points[n]));
      EXPECT_LT(error, test::kWindingMaxError) << name << " " << points[n].transpose();
      mean += error / 20;
    }
    EXPECT_LT(mean, test::kWindingMeanError) << name;
    const auto start = std::chrono::steady_clock::now();
    double sum = 0.0;
    for (const auto& p : points) sum += mesh_shape.winding_number(p);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cout << name << ": " << facts.triangle_count << " triangles, " << points.size() / seconds
              << " winding-number queries/s (sum " << sum << ")\n";
  }
}

}  // namespace
}  // namespace mgelastic::geometry
