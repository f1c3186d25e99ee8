#include "mgelastic/grid/surface_interpolation.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "mgelastic/core/error.hpp"

namespace mgelastic::grid {
namespace {

void validate(const NodeDisplacement& u) {
  require((u.nodes.array() >= 2).all(), "nodes", "need at least 2 lattice nodes on every axis");
  require(u.values.size() == 3 * std::size_t(u.nodes.cast<std::size_t>().prod()), "values",
          "need 3 components per lattice node");
}

// Weights of one axis on the nodes first, ..., first + 3 (zero on nodes outside the lattice).
struct AxisWeights {
  int first = 0;
  std::array<double, 4> w{};
};

// Adds `scale` times h D g[m] (the header's finite differences) to the weights.
void add_derivative(int m, int n, double scale, AxisWeights& a) {
  auto add = [&](int node, double weight) { a.w[node - a.first] += scale * weight; };
  if (n == 2) {
    add(0, -1);
    add(1, 1);
  } else if (m == 0) {
    add(0, -1.5);
    add(1, 2);
    add(2, -0.5);
  } else if (m == n - 1) {
    add(n - 1, 1.5);
    add(n - 2, -2);
    add(n - 3, 0.5);
  } else {
    add(m + 1, 0.5);
    add(m - 1, -0.5);
  }
}

// The 1D cubic Hermite interpolant of node values and finite-difference slopes in the cell
// [base, base + 1] at local coordinate t, as weights on nodes base - 1 .. base + 2.
AxisWeights hermite_weights(int base, double t, int n) {
  AxisWeights a;
  a.first = base - 1;
  const double t2 = t * t, t3 = t2 * t;
  a.w[1] += 2 * t3 - 3 * t2 + 1;
  a.w[2] += 3 * t2 - 2 * t3;
  add_derivative(base, n, t3 - 2 * t2 + t, a);
  add_derivative(base + 1, n, t3 - t2, a);
  return a;
}

AxisWeights linear_weights(int base, double t) {
  AxisWeights a;
  a.first = base - 1;
  a.w[1] = 1 - t;
  a.w[2] = t;
  return a;
}

// Tensor-product sum of the nodal values with per-axis weights.
Vec<3> tensor_sum(const NodeDisplacement& u, const std::array<AxisWeights, 3>& a) {
  Vec<3> result = Vec<3>::Zero();
  for (int c = 0; c < 4; ++c) {
    const int k = a[2].first + c;
    if (a[2].w[c] == 0 || k < 0 || k >= u.nodes[2]) continue;
    for (int b = 0; b < 4; ++b) {
      const int j = a[1].first + b;
      if (a[1].w[b] == 0 || j < 0 || j >= u.nodes[1]) continue;
      const double wjk = a[1].w[b] * a[2].w[c];
      for (int e = 0; e < 4; ++e) {
        const int i = a[0].first + e;
        if (a[0].w[e] == 0 || i < 0 || i >= u.nodes[0]) continue;
        result += (a[0].w[e] * wjk) * u.at(i, j, k);
      }
    }
  }
  return result;
}

Vec<3> interpolate_validated(const NodeDisplacement& u, const Vec<3>& x,
                             SurfaceInterpolation method) {
  if (!x.allFinite()) return Vec<3>::Constant(std::nan(""));
  std::array<AxisWeights, 3> weights;
  for (int a = 0; a < 3; ++a) {
    // Clamp to the lattice; points on the upper face belong to the last cell.
    const double s = std::clamp((x[a] - u.origin[a]) / u.h, 0.0, double(u.nodes[a] - 1));
    const int base = std::min(static_cast<int>(std::floor(s)), u.nodes[a] - 2);
    weights[a] = method == SurfaceInterpolation::TRICUBIC
                     ? hermite_weights(base, s - base, u.nodes[a])
                     : linear_weights(base, s - base);
  }
  return tensor_sum(u, weights);
}

}  // namespace

Vec<3> interpolate_displacement(const NodeDisplacement& u, const Vec<3>& x,
                                SurfaceInterpolation method) {
  validate(u);
  return interpolate_validated(u, x, method);
}

void displace_points(const NodeDisplacement& u, SurfaceInterpolation method, const PointRows& rest,
                     PointRows& deformed) {
  validate(u);
  deformed.resize(rest.rows(), 3);
  // Rows are independent; each reads its rest row before writing, so rest may alias deformed.
#pragma omp parallel for schedule(static)
  for (Eigen::Index p = 0; p < rest.rows(); ++p) {
    const Vec<3> x = rest.row(p).transpose();
    deformed.row(p) = (x + interpolate_validated(u, x, method)).transpose();
  }
}

}  // namespace mgelastic::grid
