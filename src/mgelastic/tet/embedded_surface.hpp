#pragma once
// A triangle surface carried by a tetrahedral mesh: each surface vertex is bound to one tet by
// four barycentric weights, so the surface follows the tets as they deform. The tet engine uses it
// to output the body's input surface (a smooth sphere, a scanned dragon) instead of the
// stair-stepped boundary of the regular tet grid that was generated from it; the grid engine does
// the same with its lattice (grid/surface_interpolation.hpp).
//
// Equation: surface vertex s with tet t = tet[s] (corners c0..c3 = mesh.tets.row(t)) and weights
// w = weights.row(s) is at
//   y_s = sum_{i=0..3} w_i x_{c_i}
// for the current mesh vertex positions x. The weights are the barycentric coordinates of the
// rest position p_s in the rest tet: w_1..3 = E^{-1} (p_s - x_{c0}) with E = [x_{c1} - x_{c0},
// x_{c2} - x_{c0}, x_{c3} - x_{c0}], w_0 = 1 - w_1 - w_2 - w_3. They sum to 1, so y_s = p_s at rest
// (to rounding) and y_s moves exactly affinely with its tet, whatever the tet's deformation.
//
// Binding: a vertex inside some tet (every weight >= -1e-12) is bound to it. A regular tet grid
// need not cover the whole surface (cubes whose center is outside are dropped), so a vertex
// inside no tet is bound to the nearest tet (least distance to the closest point on the tet) with
// the vertex's own, unclamped barycentrics (some negative): the vertex is extrapolated by that
// tet's affine motion. Tets are found through a uniform grid of bins holding every tet whose
// bounding box overlaps the bin; the nearest tet by rings of bins around the vertex.
//
// Data layout: `tet` has one entry per surface vertex (index into mesh.tets), `weights` is
// (V x 4) row-major in the order of the tet's corners, `triangles` (T x 3) row-major indexes the
// surface vertices, counter-clockwise seen from outside (as geometry::TriangleMesh).
#include <Eigen/Core>

#include "mgelastic/geometry/tet_mesh.hpp"
#include "mgelastic/geometry/tet_mesh_boundary.hpp"
#include "mgelastic/geometry/triangle_mesh.hpp"

namespace mgelastic::tet {

using SurfacePoints = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;  // V x 3

struct EmbeddedSurface {
  Eigen::VectorXi tet;
  Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor> weights;
  Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor> triangles;
  int outside_vertices = 0;           // bound to the nearest tet (extrapolated)
  double max_outside_distance = 0.0;  // largest distance of such a vertex from its tet

  Eigen::Index vertex_count() const { return tet.size(); }
};

// Binds every vertex of `surface` to a tet of `mesh` (positively oriented, as check_tet_mesh
// leaves it). Throws Error when the mesh has no tets.
EmbeddedSurface embed_surface(const geometry::TetMesh& mesh, const geometry::TriangleMesh& surface);

// The mesh's own boundary faces as an embedded surface: each boundary vertex gets weight 1 on
// its corner of a tet that holds it, so `embedded_positions` returns the mesh vertices' positions.
EmbeddedSurface boundary_as_embedded(const geometry::TetMesh& mesh,
                                     const geometry::TetMeshBoundary& boundary);

// y_s for every surface vertex from the mesh vertex positions (N x 3), in parallel.
SurfacePoints embedded_positions(const EmbeddedSurface& surface, const Eigen::MatrixX3d& positions,
                                 const Eigen::MatrixX4i& tets);

}  // namespace mgelastic::tet
