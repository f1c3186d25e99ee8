#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <thread>

#include "geometry/surface_mesh_test_support.hpp"
#include "mgelastic/geometry/winding_number.hpp"

namespace mgelastic::geometry {
namespace {

using test::make_icosphere;
using test::random_point;

// Solid angles are atan2 of O(1) quantities: round-off of a few ulps per triangle.
constexpr double kSolidAngleRoundoff = 1e-13;

// The octant triangle subtends exactly 1/8 of the sphere from the origin, which lies behind its
// right-hand normal (1, 1, 1): positive.
TEST(WindingNumber, SolidAngleOfTheOctantTriangle) {
  const Point a(1, 0, 0), b(0, 1, 0), c(0, 0, 1);
  EXPECT_NEAR(triangle_solid_angle(a, b, c, Point::Zero()), 4 * std::numbers::pi / 8,
              kSolidAngleRoundoff);
  EXPECT_NEAR(triangle_solid_angle(a, c, b, Point::Zero()), -4 * std::numbers::pi / 8,
              kSolidAngleRoundoff);
}

// A closed outward surface: the exact sum is 1 inside and 0 outside (to round-off).
TEST(WindingNumber, ExactSumIsOneInsideAndZeroOutside) {
  const TriangleMesh sphere = make_icosphere(2);
  std::mt19937 rng(3);
  for (int n = 0; n < 300; ++n) {
    const Point p = random_point(rng, 1.5);
    if (std::abs(p.norm() - 1.0) < 0.05) continue;  // between the sphere and its inscribed mesh
    EXPECT_NEAR(exact_winding_number(sphere, p), p.norm() < 1.0 ? 1.0 : 0.0, 1e-12) << p;
  }
}

// Mean and worst deviation of `fast` from the exact sum over `points`.
template <class Fast>
std::pair<double, double> deviation(const Fast& fast, const TriangleMesh& mesh,
                                    const std::vector<Point>& points) {
  double mean = 0.0, worst = 0.0;
  for (const Point& p : points) {
    const double e = std::abs(fast(p) - exact_winding_number(mesh, p));
    mean += e / static_cast<double>(points.size());
    worst = std::max(worst, e);
  }
  return {mean, worst};
}

std::vector<Point> random_points(int count, double extent, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<Point> points(count);
  for (auto& p : points) p = random_point(rng, extent);
  return points;
}

// The hierarchical evaluation agrees with the exact sum everywhere, near the surface included,
// and classifies points off the surface.
TEST(WindingNumber, HierarchicalAgreesWithExactSum) {
  const TriangleMesh sphere = make_icosphere(4);  // 5120 triangles: deep enough to use far fields
  const WindingNumber fast(sphere);
  const std::vector<Point> points = random_points(400, 2.0, 4);
  const auto [mean, worst] = deviation(fast, sphere, points);
  EXPECT_LT(mean, test::kWindingMeanError);
  EXPECT_LT(worst, test::kWindingMaxError);
  for (const Point& p : points)
    if (std::abs(p.norm() - 1.0) > 0.01) {
      EXPECT_EQ(fast(p) > 0.5, p.norm() < 1.0) << p;
    }
}

// Each added Taylor order reduces the error; beta = 3 brings the worst case below 1e-3.
TEST(WindingNumber, HigherOrderAndLargerBetaAreMoreAccurate) {
  const TriangleMesh sphere = make_icosphere(4, 1.0, Point(0.2, 0.1, -0.3));
  const auto bvh = std::make_shared<const TriangleBvh>(sphere);
  const std::vector<Point> points = random_points(200, 2.0, 5);
  const auto dipole =
      deviation(WindingNumber(bvh, {.order = ExpansionOrder::DIPOLE}), sphere, points);
  const auto first =
      deviation(WindingNumber(bvh, {.order = ExpansionOrder::FIRST}), sphere, points);
  const auto second = deviation(WindingNumber(bvh), sphere, points);
  const auto beta3 = deviation(WindingNumber(bvh, {.beta = 3.0}), sphere, points);
  EXPECT_LT(first.first, dipole.first);
  EXPECT_LT(second.first, 0.5 * first.first);
  EXPECT_LT(beta3.second, test::kWindingMaxErrorBeta3);
}

// Open surfaces (a sphere with holes) are where the generalized winding number matters: the
// hierarchical sum must still match the exact one.
TEST(WindingNumber, HierarchicalAgreesOnAnOpenSurface) {
  const TriangleMesh open = test::remove_triangles(make_icosphere(4), {0, 1, 2, 3, 500, 2000});
  const auto [mean, worst] = deviation(WindingNumber(open), open, random_points(200, 1.5, 6));
  EXPECT_LT(mean, test::kWindingMeanError);
  EXPECT_LT(worst, test::kWindingMaxError);
}

// Queries are const and allocation-free: concurrent threads get the serial answers.
TEST(WindingNumber, ConcurrentQueriesMatchSerial) {
  const WindingNumber fast(make_icosphere(3));
  std::mt19937 rng(7);
  std::vector<Point> points;
  for (int n = 0; n < 2000; ++n) points.push_back(random_point(rng, 1.5));
  std::vector<double> serial(points.size()), parallel(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) serial[i] = fast(points[i]);
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      for (std::size_t i = t; i < points.size(); i += 4) parallel[i] = fast(points[i]);
    });
  for (auto& thread : threads) thread.join();
  EXPECT_EQ(serial, parallel);
}

}  // namespace
}  // namespace mgelastic::geometry
