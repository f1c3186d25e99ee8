#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <string>

#include "mgelastic/core/error.hpp"
#include "mgelastic/grid/surface_interpolation.hpp"

namespace mgelastic::grid {
namespace {

using Field = std::function<Vec<3>(const Vec<3>&)>;

// Exactness is checked to a few hundred ulps of the field's magnitude (~1): the 64-term sums
// and the finite-difference weights round at 1e-16 each.
constexpr double kExact = 1e-12;

NodeDisplacement sample_nodes(const IVec<3>& nodes, double h, const Vec<3>& origin,
                              const Field& f) {
  NodeDisplacement u;
  u.nodes = nodes;
  u.h = h;
  u.origin = origin;
  u.values.resize(3 * std::size_t(nodes.prod()));
  for (int k = 0; k < nodes[2]; ++k)
    for (int j = 0; j < nodes[1]; ++j)
      for (int i = 0; i < nodes[0]; ++i) {
        const Vec<3> value = f(origin + h * Vec<3>(i, j, k));
        const std::size_t n = (std::size_t(k) * nodes[1] + j) * nodes[0] + i;
        for (int a = 0; a < 3; ++a) u.values[3 * n + a] = value[a];
      }
  return u;
}

Vec<3> random_point_in(const NodeDisplacement& u, std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0, 1);
  const Vec<3> extent = u.h * (u.nodes - IVec<3>::Ones()).cast<double>();
  return u.origin + Vec<3>(unit(rng), unit(rng), unit(rng)).cwiseProduct(extent);
}

// A random polynomial per component with monomials x^p y^q z^r, p, q, r <= degree.
Field random_tensor_polynomial(int degree, std::mt19937& rng) {
  std::uniform_real_distribution<double> coefficient(-1, 1);
  const int n = degree + 1;
  std::vector<double> c(3 * n * n * n);
  for (double& value : c) value = coefficient(rng);
  return [c, n](const Vec<3>& x) {
    Vec<3> value = Vec<3>::Zero();
    for (int r = 0, m = 0; r < n; ++r)
      for (int q = 0; q < n; ++q)
        for (int p = 0; p < n; ++p, ++m)
          for (int a = 0; a < 3; ++a)
            value[a] += c[3 * m + a] * std::pow(x[0], p) * std::pow(x[1], q) * std::pow(x[2], r);
    return value;
  };
}

double max_error(const NodeDisplacement& u, const Field& f, SurfaceInterpolation method,
                 int samples = 2000) {
  std::mt19937 rng(7);
  double worst = 0;
  for (int s = 0; s < samples; ++s) {
    const Vec<3> x = random_point_in(u, rng);
    worst = std::max(worst, (interpolate_displacement(u, x, method) - f(x)).norm());
  }
  return worst;
}

const IVec<3> kNodes(5, 6, 7);
const Vec<3> kOrigin(-0.3, 0.2, -0.1);
constexpr double kH = 0.17;

TEST(SurfaceInterpolation, TrilinearReproducesMultilinearFields) {
  std::mt19937 rng(1);
  const Field f = random_tensor_polynomial(1, rng);  // affine plus xy, xz, yz, xyz
  const NodeDisplacement u = sample_nodes(kNodes, kH, kOrigin, f);
  EXPECT_LT(max_error(u, f, SurfaceInterpolation::TRILINEAR), kExact);
}

// Central differences inside and second-order one-sided ones at the border are exact for
// quadratics, so the Hermite form is exact for degree <= 2 in each variable, border cells too.
TEST(SurfaceInterpolation, TricubicReproducesTriquadraticFields) {
  std::mt19937 rng(2);
  const Field f = random_tensor_polynomial(2, rng);
  const NodeDisplacement u = sample_nodes(kNodes, kH, kOrigin, f);
  EXPECT_LT(max_error(u, f, SurfaceInterpolation::TRICUBIC), kExact);
}

// ...and no further: a cubic's finite-difference slope is off by O(h^2).
TEST(SurfaceInterpolation, TricubicIsNotExactForCubics) {
  const Field f = [](const Vec<3>& x) { return Vec<3>(std::pow(x[0], 3), 0, 0); };
  const NodeDisplacement u = sample_nodes(kNodes, kH, kOrigin, f);
  EXPECT_GT(max_error(u, f, SurfaceInterpolation::TRICUBIC), 1e-2 * kH * kH * kH);
}

// One-sided difference quotients of random nodal data across interior cell faces: their jump
// is O(eps) for a C1 interpolant and O(1) for trilinear (which checks that the test can fail).
double max_gradient_jump(const NodeDisplacement& u, SurfaceInterpolation method) {
  std::mt19937 rng(3);
  const double eps = 1e-6 * u.h;
  double worst = 0;
  for (int s = 0; s < 300; ++s) {
    Vec<3> x = random_point_in(u, rng);
    const int axis = s % 3;
    x[axis] = u.origin[axis] + u.h * (1 + s % (u.nodes[axis] - 2));  // an interior face
    for (int d = 0; d < 3; ++d) {
      const Vec<3> step = eps * Vec<3>::Unit(d);
      const Vec<3> f0 = interpolate_displacement(u, x, method);
      const Vec<3> below = (f0 - interpolate_displacement(u, x - step, method)) / eps;
      const Vec<3> above = (interpolate_displacement(u, x + step, method) - f0) / eps;
      worst = std::max(worst, (above - below).norm());
    }
  }
  return worst;
}

TEST(SurfaceInterpolation, TricubicIsC1AcrossCellFaces) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> noise(-1, 1);
  NodeDisplacement u =
      sample_nodes(kNodes, kH, kOrigin, [](const Vec<3>&) { return Vec<3>::Zero().eval(); });
  for (double& value : u.values) value = noise(rng);
  // Gradients are ~1/h; second derivatives ~1/h^2, so C1 jumps are ~eps/h^2 = 1e-6/h.
  const double scale = 1 / kH;
  EXPECT_LT(max_gradient_jump(u, SurfaceInterpolation::TRICUBIC), 1e-4 * scale);
  EXPECT_GT(max_gradient_jump(u, SurfaceInterpolation::TRILINEAR), 1e-1 * scale);
}

double smooth_field_error(int cells, SurfaceInterpolation method) {
  const Field f = [](const Vec<3>& x) {
    return Vec<3>(std::sin(2 * x[0] + 1) * std::cos(3 * x[1]) * std::sin(x[2] + 0.5),
                  std::cos(x[0] - 2 * x[1] + x[2]), std::exp(0.5 * x[0]) * std::sin(2 * x[2]));
  };
  const NodeDisplacement u =
      sample_nodes(IVec<3>::Constant(cells + 1), 1.0 / cells, Vec<3>::Zero(), f);
  return max_error(u, f, method);
}

// Observed orders from the maximum error at 8, 16 and 32 cells per unit.
double observed_order(SurfaceInterpolation method, const std::string& name) {
  const double e8 = smooth_field_error(8, method), e16 = smooth_field_error(16, method),
               e32 = smooth_field_error(32, method);
  ::testing::Test::RecordProperty(name + "_order_8_16", std::to_string(std::log2(e8 / e16)));
  ::testing::Test::RecordProperty(name + "_order_16_32", std::to_string(std::log2(e16 / e32)));
  return std::min(std::log2(e8 / e16), std::log2(e16 / e32));
}

TEST(SurfaceInterpolation, TrilinearErrorConvergesWithOrderTwo) {
  EXPECT_GE(observed_order(SurfaceInterpolation::TRILINEAR, "trilinear"), 1.8);
}

// O(h^3), not Lekien-Marsden's O(h^4): the nodal derivatives are O(h^2) finite differences.
TEST(SurfaceInterpolation, TricubicErrorConvergesWithOrderThree) {
  EXPECT_GE(observed_order(SurfaceInterpolation::TRICUBIC, "tricubic"), 2.8);
}

TEST(SurfaceInterpolation, QueryPointsAreClampedToTheLattice) {
  std::mt19937 rng(5);
  const Field f = random_tensor_polynomial(2, rng);
  const NodeDisplacement u = sample_nodes(kNodes, kH, kOrigin, f);
  const Vec<3> corner = u.origin + kH * (kNodes - IVec<3>::Ones()).cast<double>();
  const Vec<3> outside = corner + Vec<3>(0.5, -0.1 - corner[1] + u.origin[1], 2.0);
  const Vec<3> clamped(corner[0], u.origin[1], corner[2]);
  for (auto method : {SurfaceInterpolation::TRILINEAR, SurfaceInterpolation::TRICUBIC})
    EXPECT_LT((interpolate_displacement(u, outside, method) - f(clamped)).norm(), kExact);
}

TEST(SurfaceInterpolation, DisplacePointsMatchesPointwiseInterpolation) {
  std::mt19937 rng(6);
  const Field f = random_tensor_polynomial(3, rng);
  const NodeDisplacement u = sample_nodes(kNodes, kH, kOrigin, f);
  PointRows rest(500, 3);
  for (Eigen::Index p = 0; p < rest.rows(); ++p) rest.row(p) = random_point_in(u, rng).transpose();
  PointRows deformed;
  displace_points(u, SurfaceInterpolation::TRICUBIC, rest, deformed);
  PointRows in_place = rest;
  displace_points(u, SurfaceInterpolation::TRICUBIC, in_place, in_place);
  ASSERT_EQ(deformed.rows(), rest.rows());
  for (Eigen::Index p = 0; p < rest.rows(); ++p) {
    const Vec<3> x = rest.row(p).transpose();
    const Vec<3> expected = x + interpolate_displacement(u, x, SurfaceInterpolation::TRICUBIC);
    EXPECT_EQ(Vec<3>(deformed.row(p).transpose()), expected);
    EXPECT_EQ(Vec<3>(in_place.row(p).transpose()), expected);
  }
}

TEST(SurfaceInterpolation, RejectsMalformedLattices) {
  NodeDisplacement u =
      sample_nodes(IVec<3>(1, 3, 3), kH, kOrigin, [](const Vec<3>& x) { return x; });
  EXPECT_THROW(interpolate_displacement(u, kOrigin, SurfaceInterpolation::TRILINEAR), Error);
  u = sample_nodes(kNodes, kH, kOrigin, [](const Vec<3>& x) { return x; });
  u.values.pop_back();
  PointRows rest(1, 3), deformed;
  rest.row(0) = kOrigin.transpose();
  EXPECT_THROW(displace_points(u, SurfaceInterpolation::TRICUBIC, rest, deformed), Error);
}

}  // namespace
}  // namespace mgelastic::grid
