#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "geometry/surface_mesh_test_support.hpp"
#include "mgelastic/core/error.hpp"
#include "mgelastic/geometry/csg.hpp"
#include "mgelastic/geometry/primitives.hpp"

namespace mgelastic::geometry {
namespace {

using test::random_point;

// contains() agrees with the analytic definitions on random points.
TEST(Primitives, ContainsMatchesAnalyticDefinitions) {
  std::mt19937 rng(1);
  const auto box = make_box(Point(0.1, 0, 0), Point(1.0, 0.6, 0.4));
  const auto sphere = make_sphere(Point(0, 0.2, 0), 0.7);
  const auto cylinder = make_cylinder(Point(0, -0.5, 0), Point(0, 0.5, 0), 0.3);
  const auto capsule = make_capsule(Point(-0.5, 0, 0), Point(0.5, 0, 0), 0.25);
  const auto torus = make_torus(Point::Zero(), Point(0, 0, 1), 0.6, 0.2);
  for (int n = 0; n < 2000; ++n) {
    const Point p = random_point(rng, 1.0);
    EXPECT_EQ(box->contains(p),
              std::abs(p.x() - 0.1) <= 0.5 && std::abs(p.y()) <= 0.3 && std::abs(p.z()) <= 0.2);
    EXPECT_EQ(sphere->contains(p), (p - Point(0, 0.2, 0)).norm() <= 0.7);
    EXPECT_EQ(cylinder->contains(p), std::hypot(p.x(), p.z()) <= 0.3 && std::abs(p.y()) <= 0.5);
    const double t = std::clamp(p.x(), -0.5, 0.5);
    EXPECT_EQ(capsule->contains(p), (p - Point(t, 0, 0)).norm() <= 0.25);
    EXPECT_EQ(torus->contains(p), std::hypot(std::hypot(p.x(), p.y()) - 0.6, p.z()) <= 0.2);
  }
}

// The signed distances are distances: |grad| = 1 (central differences) away from the medial
// axis, and exact values at known points.
TEST(Primitives, SignedDistancesHaveUnitGradient) {
  std::mt19937 rng(2);
  const std::vector<ShapePtr> shapes{make_box(Point::Zero(), Point(1, 2, 0.5)),
                                     make_sphere(Point::Zero(), 0.5),
                                     make_cylinder(Point(0, 0, -0.4), Point(0, 0, 0.4), 0.3),
                                     make_capsule(Point(0, 0, 0), Point(0.3, 0.3, 0), 0.2),
                                     make_torus(Point::Zero(), Point(0, 1, 0), 0.5, 0.1)};
  const double eps = 1e-6;
  int checked = 0;
  for (const auto& shape : shapes) {
    for (int n = 0; n < 200; ++n) {
      const Point p = random_point(rng, 1.5);
      if (std::abs(shape->signed_distance(p)) < 1e-3 || shape->signed_distance(p) < 0) continue;
      Point g;
      for (int a = 0; a < 3; ++a) {
        Point d = Point::Zero();
        d[a] = eps;
        g[a] = (shape->signed_distance(p + d) - shape->signed_distance(p - d)) / (2 * eps);
      }
      EXPECT_NEAR(g.norm(), 1.0, 1e-4);
      ++checked;
    }
  }
  EXPECT_GT(checked, 500);
  EXPECT_NEAR(make_box(Point::Zero(), Point(2, 2, 2))->signed_distance(Point(3, 0, 0)), 2.0, 1e-15);
  EXPECT_NEAR(make_sphere(Point::Zero(), 1.0)->signed_distance(Point::Zero()), -1.0, 1e-15);
}

TEST(Primitives, CsgCombinesMembership) {
  const auto a = make_sphere(Point::Zero(), 1.0);
  const auto b = make_box(Point(1, 0, 0), Point(1, 1, 1));
  const Point in_both(0.75, 0, 0), only_a(-0.5, 0, 0), only_b(1.4, 0.4, 0), neither(0, 2, 0);
  const auto u = make_union({a, b}), i = make_intersection({a, b}), d = make_difference({a, b});
  EXPECT_TRUE(u->contains(only_a) && u->contains(only_b) && !u->contains(neither));
  EXPECT_TRUE(i->contains(in_both) && !i->contains(only_a) && !i->contains(only_b));
  EXPECT_TRUE(d->contains(only_a) && !d->contains(in_both) && !d->contains(only_b));
}

TEST(Primitives, TransformMovesRotatesAndScales) {
  const auto box = make_box(Point::Zero(), Point(2, 0.2, 0.2));
  const auto moved = make_transformed(box, Point(5, 0, 0), Point(0, 0, 1), 90.0, 2.0);
  EXPECT_TRUE(moved->contains(Point(5, 1.9, 0)));  // x-bar rotated onto y, doubled
  EXPECT_FALSE(moved->contains(Point(6.9, 0, 0)));
  EXPECT_NEAR(moved->bounding_box().max().y(), 2.0, 1e-12);
}

TEST(Primitives, InvalidParametersAreNamed) {
  try {
    make_sphere(Point::Zero(), -1);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("radius"), std::string::npos);
  }
  EXPECT_THROW(make_box(Point::Zero(), Point(1, 0, 1)), Error);
  EXPECT_THROW(make_difference({make_sphere(Point::Zero(), 1)}), Error);
}

}  // namespace
}  // namespace mgelastic::geometry
