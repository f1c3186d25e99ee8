#pragma once
// Rest state of a tetrahedral body with everything the corotated method precomputes once:
// per-element stiffness K_e (12x12), rest volume, rest edge inverse Dm^{-1}, the rest second moment
// S_e = int (X - c0)(X - c0)^T dX used by the rotation energy, and lumped vertex masses.
//
// Layout: positions are 3N vectors, vertex-major (x0 y0 z0 x1 ...). Lumped mass: each element
// gives rho V / 4 to each of its vertices (row sums of the consistent mass matrix would give the
// same totals; lumping keeps M diagonal so it adds to the diagonal blocks only).
#include <Eigen/Core>
#include <vector>

#include "mgelastic/geometry/tet_mesh.hpp"
#include "mgelastic/tet/element_materials.hpp"
#include "mgelastic/tet/linear_tet_element.hpp"

namespace mgelastic::tet {

class TetBody {
 public:
  // Throws Error for a mesh with non-positive volumes or invalid materials.
  TetBody(const geometry::TetMesh& mesh, const ElementMaterials& materials);

  int vertex_count() const { return static_cast<int>(m_vertex_mass.size()); }
  int element_count() const { return static_cast<int>(m_tets.rows()); }
  const Eigen::MatrixX4i& tets() const { return m_tets; }
  const Eigen::VectorXd& rest_positions() const { return m_rest; }
  const ElementMaterials& materials() const { return m_materials; }

  const Matrix12d& stiffness(int e) const { return m_stiffness[e]; }
  double volume(int e) const { return m_volume[e]; }
  const Eigen::Matrix3d& rest_edge_inverse(int e) const { return m_dm_inverse[e]; }
  const Eigen::Matrix3d& second_moment(int e) const { return m_second_moment[e]; }
  const Eigen::VectorXd& vertex_mass() const { return m_vertex_mass; }

  // Corners of element e taken from a 3N position vector.
  TetCorners corners(int e, const Eigen::VectorXd& positions) const;

 private:
  Eigen::MatrixX4i m_tets;
  Eigen::VectorXd m_rest;
  ElementMaterials m_materials;
  std::vector<Matrix12d> m_stiffness;
  std::vector<double> m_volume;
  std::vector<Eigen::Matrix3d> m_dm_inverse;
  std::vector<Eigen::Matrix3d> m_second_moment;
  Eigen::VectorXd m_vertex_mass;
};

// Exact second moment int_T (X - c)(X - c)^T dX of a linear tetrahedron about its centroid c:
// V/20 sum_a r_a r_a^T with r_a = X_a - c (the sum r_a vanishes, dropping the second term of the
// general formula V/20 (sum r_a r_a^T + (sum r_a)(sum r_a)^T)).
Eigen::Matrix3d tet_second_moment(const TetCorners& corners);

}  // namespace mgelastic::tet
