#pragma once
// Regular tetrahedral grid covering a body: the cubes of a uniform grid that belong to the body,
// each split into six tetrahedra by the Kuhn (Freudenthal) split along the cube diagonal from its
// minimum to its maximum corner. Because every cube is split the same way, faces shared by
// neighbouring cubes are cut along the same diagonal: the mesh is conforming without alternating
// cube orientations. Vertices are shared between cubes and compacted (only used grid points).
//
// Grid: cubes of edge `cell_size` start at bbox.min(); there are ceil(extent / cell_size) cubes per
// axis (at least one), so the grid may extend past bbox.max() by less than one cell.
#include <Eigen/Geometry>
#include <functional>

#include "mgelastic/geometry/tet_mesh.hpp"

namespace mgelastic::geometry {

using InsidePredicate = std::function<bool(const Eigen::Vector3d&)>;

// Which cubes are kept.
enum class CubeSelection {
  CENTER,      // the cube's center is inside (mesh approximates the body, may cut thin parts)
  ANY_CORNER,  // any corner or the center is inside (mesh covers the body, as for embedding)
};

struct RegularTetGrid {
  TetMesh mesh;
  Eigen::Vector3i cells = Eigen::Vector3i::Zero();  // cubes per axis of the full grid
  // Grid point (i, j, k) of each mesh vertex.
  Eigen::MatrixX3i vertex_grid_index;
};

// Throws Error when cell_size <= 0, the box is empty, the grid would exceed ~2^31 points, or no
// cube is selected.
RegularTetGrid regular_tet_grid(const InsidePredicate& inside, const Eigen::AlignedBox3d& bbox,
                                double cell_size, CubeSelection selection = CubeSelection::CENTER);

}  // namespace mgelastic::geometry
