#pragma once
// The boundary surface of a tetrahedral mesh: the faces used by exactly one tetrahedron, oriented
// outward (right-hand normals away from the tetrahedron), on a compact vertex list. Used for the
// rendered surface of tet runs and for surface tractions.
#include <Eigen/Core>
#include <vector>

#include "mgelastic/geometry/tet_mesh.hpp"

namespace mgelastic::geometry {

struct TetMeshBoundary {
  std::vector<int> mesh_vertex;  // mesh vertex of each surface vertex
  Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor> triangles;  // surface vertex indices
};

// Assumes positively oriented tetrahedra (check_tet_mesh establishes it).
TetMeshBoundary tet_mesh_boundary(const TetMesh& mesh);

}  // namespace mgelastic::geometry
