#include <gtest/gtest.h>

#include <random>

#include "geometry/surface_mesh_test_support.hpp"
#include "mgelastic/geometry/triangle_bvh.hpp"

namespace mgelastic::geometry {
namespace {

// A hint only seeds the search bound: the closest distance is the same with any hint, good
// (the previous answer at a nearby point), poor (a far triangle) or invalid.
TEST(TriangleBvh, HintDoesNotChangeTheClosestDistance) {
  const TriangleBvh bvh(test::make_icosphere(3));
  const int triangles = static_cast<int>(bvh.triangles().size());
  std::mt19937 rng(31);
  std::uniform_int_distribution<int> any_triangle(0, triangles - 1);
  int previous = -1;
  for (int n = 0; n < 2000; ++n) {
    const Point p = test::random_point(rng, 1.5);
    const ClosestTriangle plain = bvh.closest_triangle(p);
    for (const int hint : {previous, any_triangle(rng), -1, triangles, plain.position}) {
      const ClosestTriangle hinted = bvh.closest_triangle(p, hint);
      EXPECT_EQ(hinted.squared_distance, plain.squared_distance) << p << " hint " << hint;
      EXPECT_EQ((hinted.point - p).squaredNorm(), plain.squared_distance);
      ASSERT_GE(hinted.position, 0);
      EXPECT_EQ(bvh.original_index()[hinted.position], hinted.triangle);
    }
    previous = plain.position;
  }
}

}  // namespace
}  // namespace mgelastic::geometry
