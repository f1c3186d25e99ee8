#pragma once
// The linear system of one implicit step and its preconditioned conjugate-gradient solve.
//
// System: A = m (M (x) I3) + k K~ on the free vertices, identity on the constrained ones
//   (M lumped vertex masses, K~ the assembled corotated stiffness in BRC form, m and k the
//   integrator's scalars, e.g. m = 1 + h alpha, k = h^2 + h beta for implicit Euler with Rayleigh
//   damping). Constrained (Dirichlet) vertices are eliminated symmetrically: their rows and
//   columns are replaced by the identity after their known values were moved to the right-hand
//   side (see StepSystem::eliminate), so A stays symmetric positive definite.
// Preconditioner: block Jacobi, the inverse of each 3x3 diagonal block of A.
// Vectors are 3N, vertex-major.
#include <Eigen/Core>
#include <vector>

#include "mgelastic/tet/brc_matrix.hpp"

namespace mgelastic::tet {

struct PcgSettings {
  double tolerance = 1e-8;  // on |r| / |b|
  int max_iterations = 2000;
};

struct PcgResult {
  int iterations = 0;
  double relative_residual = 0.0;
  bool converged = false;
};

class StepSystem {
 public:
  // `constrained[v]` != 0 marks a Dirichlet vertex. References must outlive the system.
  StepSystem(const BlockRowMatrix<double>& stiffness, const Eigen::VectorXd& vertex_mass,
             double mass_scale, double stiffness_scale, const std::vector<char>& constrained);

  int size() const { return static_cast<int>(m_mass->size()) * 3; }
  // y = A x with the Dirichlet rows and columns replaced by the identity.
  void apply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const;
  // y = (m M + k K~) x without constraints.
  void apply_unconstrained(const Eigen::VectorXd& x, Eigen::VectorXd& y) const;
  // Moves the known values of the constrained vertices (taken from `known`) into b:
  // b_free -= A_free,constrained known_c; b_c = known_c.
  void eliminate(const Eigen::VectorXd& known, Eigen::VectorXd& b) const;
  // y = P^{-1} r with P the block diagonal of A (its inverse blocks computed on the first call).
  void precondition(const Eigen::VectorXd& r, Eigen::VectorXd& y) const;
  // Recomputes the inverse diagonal blocks (after the stiffness values changed).
  void update_preconditioner();
  Eigen::SparseMatrix<double> to_sparse() const;  // constrained A, for direct solves and tests

 private:
  const BlockRowMatrix<double>* m_stiffness;
  const Eigen::VectorXd* m_mass;
  double m_mass_scale;
  double m_stiffness_scale;
  const std::vector<char>* m_constrained;
  void compute_inverse_diagonal() const;
  mutable std::vector<Eigen::Matrix3d> m_inverse_diagonal;  // empty until first needed
};

// Solves A x = b from the initial guess in x. Throws Error when the iteration produces
// non-finite values, meets a non-positive curvature p.Ap (A not SPD) or the residual grows
// beyond 1e8 |b| (divergence). Not reaching the tolerance is reported, not thrown.
PcgResult solve_pcg(const StepSystem& system, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                    const PcgSettings& settings);

}  // namespace mgelastic::tet
