#pragma once
// Bounding volume hierarchy over the triangles of a surface mesh, shared by the closest-triangle
// (distance) query and the hierarchical winding number.
//
// Layout: the triangles are copied by value (three corners each) and reordered so that every node
// covers a contiguous range [first, first + count) of `triangles()`; `original_index()` maps a
// position back to the row of the input mesh. Node 0 is the root; an inner node has two children
// and a leaf none (left = right = -1). Built by median splits of the centroids along the longest
// axis, so the depth is ceil(log2(T / leaf_size)) and an explicit traversal stack of 64 suffices.
#include <array>
#include <vector>

#include "mgelastic/geometry/triangle_mesh.hpp"

namespace mgelastic::geometry {

using Triangle = std::array<Eigen::Vector3d, 3>;

// The point of triangle abc closest to p (Ericson, Real-Time Collision Detection, 5.1.5);
// degenerate triangles fall back to their edges.
Eigen::Vector3d closest_point_on_triangle(const Point& p, const Triangle& triangle);

struct ClosestTriangle {
  double squared_distance = 0.0;
  int triangle = -1;  // row in the input mesh
  Point point = Point::Zero();
  int position = -1;  // index into TriangleBvh::triangles(): a hint for the next query
};

class TriangleBvh {
 public:
  struct Node {
    BoundingBox box;
    int first = 0;
    int count = 0;
    int left = -1;
    int right = -1;
    bool is_leaf() const { return left < 0; }
  };
  static constexpr int MAX_DEPTH = 64;

  // `mesh` must be checked (check_triangle_mesh) and have at least one triangle.
  explicit TriangleBvh(const TriangleMesh& mesh, int leaf_size = 8);

  const std::vector<Node>& nodes() const { return m_nodes; }
  const std::vector<Triangle>& triangles() const { return m_triangles; }
  const std::vector<int>& original_index() const { return m_original; }

  // Exact closest point of the surface to p; thread-safe. `hint` (a position from an earlier
  // answer, e.g. at a neighboring point) only seeds the search bound: the distance returned is
  // the same with or without it (on ties the triangle may be the hint's).
  ClosestTriangle closest_triangle(const Point& p, int hint = -1) const;

 private:
  int build(int first, int count, int leaf_size, int depth);

  std::vector<Node> m_nodes;
  std::vector<Triangle> m_triangles;
  std::vector<int> m_original;
};

}  // namespace mgelastic::geometry
