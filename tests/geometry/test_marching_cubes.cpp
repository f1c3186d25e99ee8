#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "mgelastic/core/error.hpp"
#include "mgelastic/geometry/csg.hpp"
#include "mgelastic/geometry/marching_cubes.hpp"
#include "mgelastic/geometry/primitives.hpp"

namespace mgelastic::geometry {
namespace {

// Off-lattice centers so that no symmetry of the sampling lattice hides an error.
const Point kCenter(0.013, -0.021, 0.007);

Point vertex(const TriangleMesh& s, int v) {
  return s.vertices.row(v).transpose();
}

// Every directed edge occurs once and its reverse once (closed, consistently oriented), every
// vertex is used, and the triangles around each vertex form a single fan (no pinched vertices).
::testing::AssertionResult is_closed_oriented_manifold(const TriangleMesh& s) {
  std::map<std::pair<int, int>, int> directed;
  std::vector<std::vector<std::pair<int, int>>> fans(s.vertices.rows());
  for (Eigen::Index f = 0; f < s.triangles.rows(); ++f)
    for (int c = 0; c < 3; ++c) {
      const int a = s.triangles(f, c), b = s.triangles(f, (c + 1) % 3);
      if (a == b) return ::testing::AssertionFailure() << "triangle " << f << " repeats a vertex";
      if (++directed[{a, b}] > 1) return ::testing::AssertionFailure() << "edge used twice";
      fans[a].push_back({b, s.triangles(f, (c + 2) % 3)});
    }
  for (const auto& [edge, count] : directed)
    if (!directed.count({edge.second, edge.first}))
      return ::testing::AssertionFailure() << "boundary edge " << edge.first << "-" << edge.second;
  for (std::size_t v = 0; v < fans.size(); ++v) {
    if (fans[v].empty()) return ::testing::AssertionFailure() << "unused vertex " << v;
    // Walk the fan (next -> prev of the next triangle); a single cycle visits all triangles.
    std::map<int, int> step(fans[v].begin(), fans[v].end());
    int at = fans[v][0].first;
    std::size_t visited = 0;
    do {
      at = step.at(at);
      ++visited;
    } while (at != fans[v][0].first && visited <= fans[v].size());
    if (visited != fans[v].size()) return ::testing::AssertionFailure() << "pinched vertex " << v;
  }
  return ::testing::AssertionSuccess();
}

long euler_characteristic(const TriangleMesh& s) {
  const long faces = s.triangles.rows();
  return long(s.vertices.rows()) - 3 * faces / 2 + faces;
}

// Volume enclosed by a closed mesh (divergence theorem); positive when oriented outward.
double signed_volume(const TriangleMesh& s) {
  double volume = 0;
  for (Eigen::Index f = 0; f < s.triangles.rows(); ++f)
    volume += vertex(s, s.triangles(f, 0))
                  .dot(vertex(s, s.triangles(f, 1)).cross(vertex(s, s.triangles(f, 2))));
  return volume / 6;
}

double max_distance_to_surface(const TriangleMesh& s, const Shape& shape) {
  double worst = 0;
  for (Eigen::Index v = 0; v < s.vertices.rows(); ++v)
    worst = std::max(worst, std::abs(shape.signed_distance(vertex(s, int(v)))));
  return worst;
}

double sphere_volume_error(double spacing) {
  const double r = 0.5;
  const auto sphere = make_sphere(kCenter, r);
  return std::abs(signed_volume(extract_surface(*sphere, spacing)) -
                  4.0 / 3.0 * std::numbers::pi * r * r * r);
}

// A shape's distance times 2^exponent (exact in floating point, so every interpolation parameter
// stays the same), counting its queries. At 2^-6 no block of the narrow band is far enough to
// skip: the full sampling.
class CountedShape final : public Shape {
 public:
  CountedShape(ShapePtr shape, int exponent) : m_shape(std::move(shape)), m_exponent(exponent) {}
  double signed_distance(const Point& p) const override {
#pragma omp atomic
    ++queries;
    return std::ldexp(m_shape->signed_distance(p), m_exponent);
  }
  BoundingBox bounding_box() const override {
    return m_shape->bounding_box();
  }
  mutable long queries = 0;

 private:
  ShapePtr m_shape;
  int m_exponent;
};

// The narrow band queries a fraction of the samples and gives, bit for bit, the mesh of the full
// sampling: same vertices, same triangles.
TEST(MarchingCubes, NarrowBandSamplingGivesTheFullSamplingsMesh) {
  const ShapePtr ring = make_difference(
      {make_torus(kCenter, Point(0.3, 1, 0.2), 0.6, 0.25),
       make_cylinder(kCenter + Point(0.61, -1, 0), kCenter + Point(0.58, 1, 0.05), 0.1)});
  const double spacing = 0.02;
  const CountedShape banded(ring, 0), full(ring, -6);
  const TriangleMesh fast = extract_surface(banded, spacing);
  const TriangleMesh reference = extract_surface(full, spacing);
  ASSERT_TRUE(is_closed_oriented_manifold(fast));
  EXPECT_EQ(fast.triangles, reference.triangles);
  EXPECT_EQ(fast.vertices, reference.vertices);
  EXPECT_LT(banded.queries, full.queries / 3);
}

TEST(MarchingCubes, SphereIsClosedManifoldOfGenusZero) {
  const auto sphere = make_sphere(kCenter, 0.5);
  const TriangleMesh s = extract_surface(*sphere, 0.07);
  ASSERT_GT(s.triangles.rows(), 100);
  EXPECT_TRUE(is_closed_oriented_manifold(s));
  EXPECT_EQ(euler_characteristic(s), 2);
}

TEST(MarchingCubes, TorusIsClosedManifoldOfGenusOne) {
  const auto torus = make_torus(kCenter, Point(0.2, 0.3, 1).normalized(), 0.5, 0.2);
  const TriangleMesh s = extract_surface(*torus, 0.05);
  EXPECT_TRUE(is_closed_oriented_manifold(s));
  EXPECT_EQ(euler_characteristic(s), 0);
}

TEST(MarchingCubes, BoxIsClosedManifoldOfGenusZero) {
  const auto box = make_box(kCenter, Point(0.8, 0.5, 0.3));
  const TriangleMesh s = extract_surface(*box, 0.06);
  EXPECT_TRUE(is_closed_oriented_manifold(s));
  EXPECT_EQ(euler_characteristic(s), 2);
}

// Box faces through samples make exact zeros; clamped edge parameters keep every triangle
// non-degenerate while the mesh stays closed.
TEST(MarchingCubes, ExactZeroSamplesGiveNoDegenerateTriangles) {
  const auto box = make_box(Point::Zero(), Point(1, 1, 1));
  const TriangleMesh s = extract_surface(*box, 0.125);  // samples at +-0.5 exactly
  EXPECT_TRUE(is_closed_oriented_manifold(s));
  EXPECT_EQ(euler_characteristic(s), 2);
  double smallest = INFINITY;
  for (Eigen::Index f = 0; f < s.triangles.rows(); ++f) {
    const Point a = vertex(s, s.triangles(f, 0));
    smallest =
        std::min(smallest,
                 (vertex(s, s.triangles(f, 1)) - a).cross(vertex(s, s.triangles(f, 2)) - a).norm());
  }
  EXPECT_GT(smallest, 0.0);
}

// A box that clips the shape: the outermost samples count as outside, capping the cut.
TEST(MarchingCubes, ClippingBoxCapsTheSurface) {
  const auto sphere = make_sphere(kCenter, 0.5);
  const BoundingBox half(Point(-0.6, -0.6, -0.6), Point(0.6, 0.6, 0.0));
  const TriangleMesh s = extract_surface(*sphere, 0.05, half);
  EXPECT_TRUE(is_closed_oriented_manifold(s));
  EXPECT_EQ(euler_characteristic(s), 2);
}

// Every triangle of a sphere faces away from its center, and the enclosed volume is positive.
TEST(MarchingCubes, TrianglesFaceOutward) {
  const auto sphere = make_sphere(kCenter, 0.5);
  const TriangleMesh s = extract_surface(*sphere, 0.05);
  EXPECT_GT(signed_volume(s), 0.0);
  int inward = 0;
  for (Eigen::Index f = 0; f < s.triangles.rows(); ++f) {
    const Point a = vertex(s, s.triangles(f, 0)), b = vertex(s, s.triangles(f, 1)),
                c = vertex(s, s.triangles(f, 2));
    inward += (b - a).cross(c - a).dot((a + b + c) / 3 - kCenter) <= 0;
  }
  EXPECT_EQ(inward, 0);
}

// Linear interpolation of the distance along a lattice edge of length L (up to sqrt(3) h for
// Kuhn diagonals) misplaces the vertex by at most ~ L^2 / (8 r) on a sphere of radius r, i.e.
// 0.75 h^2 for r = 0.5 (measured: 0.66-0.73 h^2).
TEST(MarchingCubes, VerticesLieWithinSpacingSquaredOfSurface) {
  const auto sphere = make_sphere(kCenter, 0.5);
  for (double h : {0.1, 0.05, 0.025}) {
    const double distance = max_distance_to_surface(extract_surface(*sphere, h), *sphere);
    RecordProperty("distance_over_h2_" + std::to_string(h), std::to_string(distance / (h * h)));
    EXPECT_LT(distance, h * h) << h;
  }
}

// The enclosed volume converges with order 2 (slopes over two halvings of the spacing).
TEST(MarchingCubes, EnclosedVolumeConvergesWithOrderTwo) {
  const double e1 = sphere_volume_error(0.1), e2 = sphere_volume_error(0.05),
               e3 = sphere_volume_error(0.025);
  const double order12 = std::log2(e1 / e2), order23 = std::log2(e2 / e3);
  RecordProperty("order_coarse", std::to_string(order12));
  RecordProperty("order_fine", std::to_string(order23));
  EXPECT_GE(order12, 1.8);
  EXPECT_GE(order23, 1.8);
}

TEST(MarchingCubes, RejectsBadSpacingAndOversizedLattices) {
  const auto sphere = make_sphere(Point::Zero(), 1.0);
  EXPECT_THROW(extract_surface(*sphere, 0.0), Error);
  EXPECT_THROW(extract_surface(*sphere, -0.1), Error);
  EXPECT_THROW(extract_surface(*sphere, std::nan("")), Error);
  EXPECT_THROW(extract_surface(*sphere, 1e-4), Error);                // ~8e12 samples
  EXPECT_THROW(extract_surface(*sphere, 0.1, BoundingBox()), Error);  // empty box
}

}  // namespace
}  // namespace mgelastic::geometry
