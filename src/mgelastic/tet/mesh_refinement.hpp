#pragma once
// Uniform ("red") refinement of a tetrahedral mesh: every tetrahedron is split into eight by its
// edge midpoints (Bey 1995): four corner tetrahedra and four around the shortest of the three
// diagonals of the inner octahedron (the shortest keeps the children's shape quality bounded).
// Midpoints are shared between neighbouring tetrahedra, so the refined mesh is conforming; every
// child keeps positive orientation (the last two vertices swapped where needed) and its parent's
// element tag. Used to build the same body at several resolutions (multigrid rate across mesh
// sizes, benchmarks of graded real meshes at >= 500k tets).
#include "mgelastic/geometry/tet_mesh.hpp"

namespace mgelastic::tet {

// Vertices: the parent's vertices first (same indices), then one per edge.
geometry::TetMesh refine_uniform(const geometry::TetMesh& mesh);

}  // namespace mgelastic::tet
