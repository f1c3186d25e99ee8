#pragma once
// Assembly of the corotated stiffness and forces (Georgii & Westermann 2008, Sec. 2 and 4.2).
//
// Per element e with rotation Q_e (blockwise on the four vertices), rest positions X_e and
// current positions x_e:
//   rotated stiffness   K~_e = Q_e K_e Q_e^T      (block (a,b) = Q K_ab Q^T)
//   elastic force       f_e  = -Q_e K_e (Q_e^T x_e - X_e)   (= f^0_e - K~_e x_e, f^0_e = Q K X)
//   elastic energy      W_e  = 1/2 (Q^T x - X)^T K (Q^T x - X)
// K~ is assembled into a BlockRowMatrix with the tet pattern. Each element stores direct
// references (indices into the block value array) to its 16 destination blocks, found once by
// search at construction, so the per-step assembly does no search. K~ is symmetric: only the
// upper blocks (row <= column) are summed, each lower block is copied as its mirror's transpose.
// For parallel assembly without
// races the references are also stored transposed: per destination block, the (element, local
// block) pairs that add to it, in increasing element order. One parallel loop over destination
// blocks then gathers its sum (one fork/join per assembly, no colouring barriers, no atomics).
//
// Cost: the element matrices are never read per step. With the shape gradients g_a (rest), the
// Lame parameters and the volume V of an isotropic linear element,
//   K_ab = V (lambda g_a g_b^T + mu g_b g_a^T + mu (g_a . g_b) I),
// so with h_a = Q g_a (rotated gradients, computed once per element and step)
//   Q K_ab Q^T = V (lambda h_a h_b^T + mu h_b h_a^T + mu (g_a . g_b) I),
// two outer products per block (the last term does not depend on Q: summed once per block) instead
// of two 3x3 matrix products and a 72-byte block load (the 12x12 K_e are 1152 bytes per element:
// streaming them dominated the assembly). Likewise the force K_e d (d = Q^T x - X, per corner) is V
// sigma(H) g_a with H = sum_b d_b g_b^T and sigma(H) = lambda tr(H) I + mu (H + H^T) (the element's
// constant stress).
#include <Eigen/Core>
#include <array>
#include <vector>

#include "mgelastic/tet/brc_matrix.hpp"
#include "mgelastic/tet/rotation_field.hpp"
#include "mgelastic/tet/tet_body.hpp"

namespace mgelastic::tet {

class CorotatedAssembler {
 public:
  explicit CorotatedAssembler(const TetBody& body);

  const BlockRowMatrix<double>& stiffness() const { return m_stiffness; }
  BlockRowMatrix<double>& stiffness() { return m_stiffness; }
  // refs[e][4 a + b] = index of block (tets(e,a), tets(e,b)) in stiffness().
  const std::vector<std::array<int, 16>>& block_refs() const { return m_refs; }

  // stiffness() <- sum_e Q_e K_e Q_e^T using the stored block references.
  void assemble(const RotationField& rotations);
  // The same sum, scattering element by element and finding every destination block by binary
  // search from the stored 12x12 K_e (serial reference and baseline; equal to round-off).
  void assemble_by_search(const RotationField& rotations);

  // sum_e f_e: elastic forces at positions x (3N) with the given rotations.
  Eigen::VectorXd elastic_forces(const RotationField& rotations, const Eigen::VectorXd& x) const;
  double elastic_energy(const RotationField& rotations, const Eigen::VectorXd& x) const;

 private:
  const TetBody* m_body;
  BlockRowMatrix<double> m_stiffness;
  std::vector<std::array<int, 16>> m_refs;
  // Transposed references: sources of block k are m_sources[m_source_offsets[k] ..
  // m_source_offsets[k+1]), each 16 e + (4 a + b).
  // Only upper blocks (row <= column) have sources; lower blocks have none.
  std::vector<int> m_source_offsets;
  std::vector<int> m_sources;
  // Per block: index of its transpose when it is a lower block (copied from it), else -1.
  std::vector<int> m_mirror;
  // Per block: sum of mu V (g_a . g_b) over its sources (the rotation-independent diagonal).
  std::vector<double> m_shifts;
  // Per element: rest shape gradients (columns g_a), (lambda V, mu V), rotated gradients Q g_a
  // (padded to 4 rows, last row 0, so the block sums run on whole vector registers).
  std::vector<Eigen::Matrix<double, 3, 4>> m_gradients;
  std::vector<Eigen::Vector2d> m_lame_volume;
  std::vector<Eigen::Matrix4d> m_rotated;
  // Vertex -> element corners 4 e + a (CSR), for gathering element forces.
  std::vector<int> m_corner_offsets;
  std::vector<int> m_corners;
};

// Rotated element stiffness Q K Q^T (blockwise).
Matrix12d rotate_stiffness(const Matrix12d& k, const Eigen::Matrix3d& q);

}  // namespace mgelastic::tet
