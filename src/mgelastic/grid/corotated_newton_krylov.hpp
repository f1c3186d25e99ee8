#pragma once
// Minimal-residual (GCR) combination of preconditioned directions for the Newton-Krylov step of
// the co-rotated outer iteration (corotated_multigrid.hpp, CorotatedOuter::NEWTON_KRYLOV).
//
// The frozen-rotation (Picard) cycle solves with the quasi-linear matrix A(R) at R = R(x_k) but
// misses the change of R(F) with the displacement, so it contracts only ~0.47 per refresh even
// with an exact inner solve. The Newton step solves J d = r(x_k) for the true Jacobian
// J = dF/dx (F = the non-linear co-rotated operator, r = b - F), right-preconditioned by the
// frozen V-cycle B ~ A(R)^-1: directions z_j = B s_{j-1} with s the current linear residual,
// w_j = J z_j (a finite difference of the matrix-free non-linear residual, which needs no
// derivative of the polar decomposition), and the correction d = Z a with
//   a = argmin || r_0 - W a ||_2,   s_j = r_0 - W a   (GCR / FGMRES on the columns of W).
// With one direction this is the Picard cycle with the step length that minimizes the
// linearized residual.
//
// Vectors are the finest level's interior variables in the order of CorotatedRows::target.
#include <Eigen/Core>
#include <vector>

namespace mgelastic::grid {

class MinimalResidualCombination {
 public:
  explicit MinimalResidualCombination(Eigen::VectorXd initial_residual);
  // Adds a direction z and its image w = J z; updates the coefficients. A w that lies in the
  // span of the earlier ones gets weight zero.
  void add(const Eigen::VectorXd& direction, const Eigen::VectorXd& image);
  // r_0 - W a: the linearized residual after the correction.
  const Eigen::VectorXd& residual() const { return m_residual; }
  // Z a: the correction of the unknowns.
  Eigen::VectorXd correction() const;
  int directions() const { return static_cast<int>(m_z.size()); }

 private:
  Eigen::VectorXd m_initial, m_residual, m_coefficients;
  std::vector<Eigen::VectorXd> m_z, m_w;
};

}  // namespace mgelastic::grid
