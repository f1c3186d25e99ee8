#pragma once
// Minimal-residual (GCR) combination of preconditioned directions for the Newton-Krylov step of
// the co-rotated outer iteration (corotated_multigrid.hpp, CorotatedOuter::NEWTON_KRYLOV).
//
// The frozen-rotation (Picard) cycle solves with the quasi-linear matrix A(R) at R = R(x_k) but
// misses the change of R(F) with the displacement, so it contracts only ~0.47 per refresh even
// with an exact inner solve. The Newton step solves J d = r(x_k) for the true Jacobian
// J = dF/dx (F = the non-linear co-rotated operator, r = b - F), right-preconditioned by the
// frozen V-cycle B ~ A(R)^-1: directions z_j = B s_{j-1} with s the current linear residual,
// images w_j of the directions, and the correction d = Z a with
//   a = argmin || r_0 - W a ||_2,   s_j = r_0 - W a   (GCR / FGMRES on the columns of W).
// Images: the first cycle direction's is its chord w = r(x) - r(x + z) (one matrix-free
// residual, no derivative of the polar decomposition), exact for the full step. The tangent
// J z at x is no model of that step where it starts far from the solution: when a prescribed
// motion has just moved the Dirichlet cells, the cells beside them are strained by O(1) and J
// there is dominated by rotations the step removes (the keyframed example arm at 192 cells:
// tangent images left the residual at 0.99-1.0 per step, the chord 0.06-0.2). The other
// directions keep tangents (forward differences): the recycled corrections, whose scale is not
// this step's (chords cost the swinging bar 0.11 -> 0.22 per step), and the later directions of
// one Newton step, which correct a linearized residual (chords: bent bar 0.82 -> 0.93 per cycle).
// The first cycle on the rest rotations (identity, as built; no cycle since) takes the frozen
// system's residual for its first direction, B (s_0 + r_frozen - r_0): there A(I) is the linear
// model of the step, a better one than the non-linear residual at a start whose prescribed cells
// have jumped (the arm's first step 0.54 -> 0.06; at one cycle per step a poor first step is not
// made up later). On later cycles the rest rotations are stale (the linear model there cost the
// swinging bar at k = 5 0.24 -> 0.32 per step). With one direction and no recycling the step is
// the Picard cycle with the step length that minimizes the residual along the chord.
//
// Vectors are the finest level's interior variables in the order of CorotatedRows::target.
#include <Eigen/Core>
#include <vector>

namespace mgelastic::grid {

class MinimalResidualCombination {
 public:
  explicit MinimalResidualCombination(Eigen::VectorXd initial_residual);
  // Adds a direction z and its image w = J z; updates the coefficients. A w that lies in the
  // span of the earlier ones (within 1e-10 of its norm) gets weight zero. The images are
  // orthonormalized as they come (Gram-Schmidt, twice), so an addition costs a few passes over
  // the vectors and no storage beyond them (the finest level of a 256-cell scene has 1.5 M
  // unknowns: a dense n x k copy per addition paged in ~12 MB per column).
  void add(Eigen::VectorXd direction, Eigen::VectorXd image);
  // r_0 - W a: the linearized residual after the correction.
  const Eigen::VectorXd& residual() const { return m_residual; }
  // Z a: the correction of the unknowns.
  Eigen::VectorXd correction() const;
  int directions() const { return static_cast<int>(m_z.size()); }

 private:
  Eigen::VectorXd coefficients() const;

  Eigen::VectorXd m_initial, m_residual;
  std::vector<Eigen::VectorXd> m_z, m_q;  // directions; orthonormal images of the kept ones
  std::vector<int> m_kept;                // direction of each q
  Eigen::MatrixXd m_r;                    // W_kept = Q R (upper triangular)
  std::vector<double> m_q_dot_r0;         // Q^T r_0
};

}  // namespace mgelastic::grid
