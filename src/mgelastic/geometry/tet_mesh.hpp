#pragma once
// Tetrahedral mesh data shared by the readers, the grid generator and the tet engine.
//
// Layout: `vertices` is N x 3 (one row per vertex, x y z), `tets` is M x 4 (one row per
// tetrahedron, zero-based vertex indices), `element_tags` is empty or has M entries (material id /
// region tag per tetrahedron, e.g. Gmsh physical tag or MEDIT reference).
// Orientation convention: the signed volume (x1-x0) . ((x2-x0) x (x3-x0)) / 6 is positive.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace mgelastic::geometry {

struct TetMesh {
  Eigen::MatrixX3d vertices;
  Eigen::MatrixX4i tets;
  Eigen::VectorXi element_tags;

  int vertex_count() const { return static_cast<int>(vertices.rows()); }
  int tet_count() const { return static_cast<int>(tets.rows()); }
  // The four corners of tetrahedron t as the columns of a 3x4 matrix.
  Eigen::Matrix<double, 3, 4> corners(int t) const;
};

// Six times the signed volume of the tetrahedron with corners p0..p3.
double signed_volume6(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                      const Eigen::Vector3d& p2, const Eigen::Vector3d& p3);

// What to do with a tetrahedron whose signed volume is negative.
enum class InvertedTets {
  REJECT,  // strict: throw naming the element
  FIX,     // swap its last two vertices (a pure relabelling; the geometry is unchanged)
};

struct TetMeshCheckOptions {
  InvertedTets inverted = InvertedTets::FIX;
  // A tetrahedron is degenerate when |6 V| <= relative_zero_volume * (longest edge)^3.
  double relative_zero_volume = 1e-12;
};

// Checks and normalizes a freshly read mesh: finite coordinates, indices in range, four distinct
// vertices per tet, tag count, no zero-volume tets, consistent orientation. `source` names the
// file and `element_lines` (empty, or one line number per tet) lets errors name the line.
// Returns the number of tetrahedra whose orientation was fixed. Throws mgelastic::Error.
int check_tet_mesh(TetMesh& mesh, const TetMeshCheckOptions& options, const std::string& source,
                   const std::vector<long>& element_lines = {});

}  // namespace mgelastic::geometry
