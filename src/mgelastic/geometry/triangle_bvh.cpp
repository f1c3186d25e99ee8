#include "mgelastic/geometry/triangle_bvh.hpp"

#include <algorithm>
#include <limits>
#include <numeric>

namespace mgelastic::geometry {
namespace {

Eigen::Vector3d closest_point_on_segment(const Point& p, const Point& a, const Point& b) {
  const Eigen::Vector3d ab = b - a;
  const double length2 = ab.squaredNorm();
  if (length2 <= 0.0) return a;
  return a + std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) * ab;
}

Eigen::Vector3d closest_point_on_edges(const Point& p, const Triangle& t) {
  Eigen::Vector3d best = closest_point_on_segment(p, t[0], t[1]);
  for (const auto& candidate :
       {closest_point_on_segment(p, t[1], t[2]), closest_point_on_segment(p, t[2], t[0])})
    if ((candidate - p).squaredNorm() < (best - p).squaredNorm()) best = candidate;
  return best;
}

}  // namespace

Eigen::Vector3d closest_point_on_triangle(const Point& p, const Triangle& t) {
  const Point &a = t[0], &b = t[1], &c = t[2];
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  // Voronoi regions of the vertices and edges first; the face region last.
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0 && d1 - d3 > 0) return a + d1 / (d1 - d3) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0 && d2 - d6 > 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0 && (d4 - d3) + (d5 - d6) > 0)
    return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double sum = va + vb + vc;
  // A degenerate (zero-area) triangle has no face region: its closest point lies on an edge.
  if (!(sum > 0)) return closest_point_on_edges(p, t);
  return a + (vb / sum) * ab + (vc / sum) * ac;
}

TriangleBvh::TriangleBvh(const TriangleMesh& mesh, int leaf_size) {
  const int n = static_cast<int>(mesh.triangle_count());
  m_triangles.resize(n);
  for (int t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) m_triangles[t][k] = mesh.vertices.row(mesh.triangles(t, k));
  m_original.resize(n);
  std::iota(m_original.begin(), m_original.end(), 0);
  m_nodes.reserve(4 * n / std::max(leaf_size, 1) + 1);
  build(0, n, std::max(leaf_size, 1), 0);
  // Store the corners in tree order so each leaf reads contiguous memory.
  std::vector<Triangle> ordered(n);
  for (int i = 0; i < n; ++i) ordered[i] = m_triangles[m_original[i]];
  m_triangles = std::move(ordered);
}

int TriangleBvh::build(int first, int count, int leaf_size, int depth) {
  const int id = static_cast<int>(m_nodes.size());
  m_nodes.push_back(Node{BoundingBox(), first, count, -1, -1});
  BoundingBox box, centroids;
  for (int i = first; i < first + count; ++i) {
    const Triangle& t = m_triangles[m_original[i]];
    for (const auto& x : t) box.extend(x);
    centroids.extend(((t[0] + t[1] + t[2]) / 3.0).eval());
  }
  m_nodes[id].box = box;
  if (count <= leaf_size || depth + 2 >= MAX_DEPTH) return id;
  // Median split along the longest centroid extent: balanced, hence shallow.
  int axis = 0;
  centroids.sizes().maxCoeff(&axis);
  const auto key = [&](int t) {
    return m_triangles[t][0][axis] + m_triangles[t][1][axis] + m_triangles[t][2][axis];
  };
  const int half = count / 2;
  std::nth_element(m_original.begin() + first, m_original.begin() + first + half,
                   m_original.begin() + first + count,
                   [&](int s, int t) { return key(s) < key(t); });
  const int left = build(first, half, leaf_size, depth + 1);
  const int right = build(first + half, count - half, leaf_size, depth + 1);
  m_nodes[id].left = left;
  m_nodes[id].right = right;
  return id;
}

ClosestTriangle TriangleBvh::closest_triangle(const Point& p, int hint) const {
  const auto candidate = [&](int i) {
    const Eigen::Vector3d q = closest_point_on_triangle(p, m_triangles[i]);
    return ClosestTriangle{(q - p).squaredNorm(), m_original[i], q, i};
  };
  ClosestTriangle best;
  best.squared_distance = std::numeric_limits<double>::infinity();
  // Along a voxelization row the closest triangle changes rarely: its distance prunes most nodes.
  if (hint >= 0 && hint < static_cast<int>(m_triangles.size())) best = candidate(hint);
  std::array<int, MAX_DEPTH> stack;
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = m_nodes[stack[--top]];
    if (node.box.squaredExteriorDistance(p) >= best.squared_distance) continue;
    if (node.is_leaf()) {
      for (int i = node.first; i < node.first + node.count; ++i) {
        const ClosestTriangle c = candidate(i);
        if (c.squared_distance < best.squared_distance) best = c;
      }
      continue;
    }
    // Visit the nearer child first (pushed last) so the bound tightens early.
    const double dl = m_nodes[node.left].box.squaredExteriorDistance(p);
    const double dr = m_nodes[node.right].box.squaredExteriorDistance(p);
    stack[top++] = dl < dr ? node.right : node.left;
    stack[top++] = dl < dr ? node.left : node.right;
  }
  return best;
}

}  // namespace mgelastic::geometry
