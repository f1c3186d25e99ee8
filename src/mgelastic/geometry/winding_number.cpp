#include "mgelastic/geometry/winding_number.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace mgelastic::geometry {

double triangle_solid_angle(const Point& a, const Point& b, const Point& c, const Point& q) {
  const Eigen::Vector3d x = a - q, y = b - q, z = c - q;
  const double lx = x.norm(), ly = y.norm(), lz = z.norm();
  const double numerator = x.dot(y.cross(z));
  const double denominator = lx * ly * lz + x.dot(y) * lz + y.dot(z) * lx + z.dot(x) * ly;
  // atan2 resolves the branch: the solid angle exceeds pi when the denominator is negative.
  return 2.0 * std::atan2(numerator, denominator);
}

double exact_winding_number(const TriangleMesh& mesh, const Point& q) {
  double sum = 0.0;
  for (Eigen::Index t = 0; t < mesh.triangle_count(); ++t)
    sum += triangle_solid_angle(mesh.vertices.row(mesh.triangles(t, 0)).transpose(),
                                mesh.vertices.row(mesh.triangles(t, 1)).transpose(),
                                mesh.vertices.row(mesh.triangles(t, 2)).transpose(), q);
  return sum / (4.0 * std::numbers::pi);
}

WindingNumber::WindingNumber(std::shared_ptr<const TriangleBvh> bvh, WindingNumberOptions options)
    : m_bvh(std::move(bvh)), m_options(options) {
  // Each node sums its own triangle range: O(T log T) in all, and no moment-shifting algebra.
  m_expansions.reserve(m_bvh->nodes().size());
  for (const TriangleBvh::Node& node : m_bvh->nodes()) m_expansions.push_back(expand(node));
}

WindingNumber::WindingNumber(const TriangleMesh& mesh, WindingNumberOptions options)
    : WindingNumber(std::make_shared<const TriangleBvh>(mesh), options) {}

WindingNumber::Expansion WindingNumber::expand(const TriangleBvh::Node& node) const {
  const auto& triangles = m_bvh->triangles();
  Expansion e;
  double area = 0.0;
  for (int i = node.first; i < node.first + node.count; ++i) {
    const Triangle& t = triangles[i];
    const Eigen::Vector3d area_normal = 0.5 * (t[1] - t[0]).cross(t[2] - t[0]);
    const double a = area_normal.norm();
    e.center += a * (t[0] + t[1] + t[2]) / 3.0;
    area += a;
    e.dipole += area_normal;
  }
  // The area-weighted centroid keeps the expansion's error smallest; a node of degenerate
  // triangles contributes nothing anyway, so its box centre will do.
  e.center = area > 0.0 ? Eigen::Vector3d(e.center / area) : Eigen::Vector3d(node.box.center());
  for (int i = node.first; i < node.first + node.count; ++i) {
    const Triangle& t = triangles[i];
    const Eigen::Vector3d area_normal = 0.5 * (t[1] - t[0]).cross(t[2] - t[0]);
    Eigen::Matrix3d quadratic = Eigen::Matrix3d::Zero();  // 12/a int_t d d^T dA
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const auto& x : t) {
      const Eigen::Vector3d d = x - e.center;
      e.radius = std::max(e.radius, d.norm());
      quadratic += d * d.transpose();
      sum += d;
    }
    quadratic += sum * sum.transpose();
    e.moment += area_normal * (sum / 3.0).transpose();
    for (int k = 0; k < 3; ++k) e.second[k] += area_normal[k] / 12.0 * quadratic;
  }
  return e;
}

double WindingNumber::far_field(const Expansion& e, const Point& q) const {
  const Eigen::Vector3d r = e.center - q;
  const double d2 = r.squaredNorm();
  const double inv_d2 = 1.0 / d2;
  const double inv_d3 = std::sqrt(inv_d2) * inv_d2;
  double w = r.dot(e.dipole) * inv_d3;
  if (m_options.order != ExpansionOrder::DIPOLE)
    w += (e.moment.trace() - 3.0 * r.dot(e.moment * r) * inv_d2) * inv_d3;
  if (m_options.order == ExpansionOrder::SECOND) {
    // 1/2 [-3 (2 r.u + sum_i r_i tr S_i) / |r|^5 + 15 sum_i r_i (r^T S_i r) / |r|^7],
    // u_k = sum_i (S_i)_ik.
    double r_trace = 0.0, r_u = 0.0, r_srr = 0.0;
    for (int i = 0; i < 3; ++i) {
      r_trace += r[i] * e.second[i].trace();
      r_u += e.second[i].row(i).dot(r);
      r_srr += r[i] * r.dot(e.second[i] * r);
    }
    w += 0.5 * (-3.0 * (2.0 * r_u + r_trace) + 15.0 * r_srr * inv_d2) * inv_d2 * inv_d3;
  }
  return w / (4.0 * std::numbers::pi);
}

double WindingNumber::operator()(const Point& q) const {
  const auto& nodes = m_bvh->nodes();
  const auto& triangles = m_bvh->triangles();
  double solid_angle = 0.0;  // near-field sum, steradians
  double w_far = 0.0;
  std::array<int, TriangleBvh::MAX_DEPTH> stack;
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const int id = stack[--top];
    const Expansion& e = m_expansions[id];
    const TriangleBvh::Node& node = nodes[id];
    if ((q - e.center).squaredNorm() > m_options.beta * m_options.beta * e.radius * e.radius) {
      w_far += far_field(e, q);
    } else if (node.is_leaf()) {
      for (int i = node.first; i < node.first + node.count; ++i)
        solid_angle += triangle_solid_angle(triangles[i][0], triangles[i][1], triangles[i][2], q);
    } else {
      stack[top++] = node.left;
      stack[top++] = node.right;
    }
  }
  return w_far + solid_angle / (4.0 * std::numbers::pi);
}

}  // namespace mgelastic::geometry
