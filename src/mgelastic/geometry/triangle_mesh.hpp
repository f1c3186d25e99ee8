#pragma once
// Triangle surface meshes (indexed face sets) and the facts that decide whether such a mesh bounds
// a solid: boundary and non-manifold edges, orientation consistency, components, enclosed volume.
//
// The signed volume is sum_t (a - o).((b - o) x (c - o)) / 6 with o the bounding box centre: the
// enclosed volume (positive when outward) for a closed mesh, origin-dependent for an open one.
// Triangles with a repeated corner count as degenerate and take no part in the edge counts.
//
// Data layout: `vertices` is (V x 3) row-major, one vertex position per row; `triangles` is
// (T x 3) row-major, three 0-based vertex indices per row, counter-clockwise seen from outside
// (so the right-hand normal points out of the solid).
#include <Eigen/Core>
#include <string>

#include "mgelastic/geometry/shape.hpp"

namespace mgelastic::geometry {

struct TriangleMesh {
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> vertices;
  Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor> triangles;

  Eigen::Index vertex_count() const { return vertices.rows(); }
  Eigen::Index triangle_count() const { return triangles.rows(); }
};

struct MeshFacts {
  Eigen::Index vertex_count = 0;
  Eigen::Index triangle_count = 0;
  BoundingBox bounding_box;               // of the vertices used by triangles
  Eigen::Index boundary_edges = 0;        // undirected edges used by exactly one triangle
  Eigen::Index non_manifold_edges = 0;    // undirected edges used by three or more triangles
  Eigen::Index inconsistent_edges = 0;    // two-triangle edges traversed twice the same way
  bool closed = false;                    // no boundary edges
  bool manifold = false;                  // edge-manifold: no edge has more than two triangles
  bool consistently_oriented = false;     // no inconsistent edges
  int components = 0;                     // connected through shared vertices
  double signed_volume = 0.0;             // divergence theorem about the box centre
  Eigen::Index degenerate_triangles = 0;  // repeated vertex or (relatively) zero area
};

// Checks indices are in range and coordinates finite; throws Error naming `source` and the
// triangle or vertex index otherwise. Every other function here assumes a checked mesh.
void check_triangle_mesh(const TriangleMesh& mesh, const std::string& source);

MeshFacts mesh_facts(const TriangleMesh& mesh);

// Reverses every triangle (swaps its last two corners), turning an inside-out mesh outward.
void flip_orientation(TriangleMesh& mesh);

}  // namespace mgelastic::geometry
