#pragma once
// Anderson acceleration of the co-rotated outer (rotation refresh) iteration.
//
// The frozen-rotation (Picard) iteration u -> g(u) = one V-cycle on the quasi-linear system (14)
// with R = R(u) contracts the non-linear residual by only ~0.46 per refresh even with an exact
// inner solve (24x6x6 bent cantilever, nu = 0.475; docs/grid-engine.md), so one V-cycle per
// refresh cannot beat that. Anderson mixing (type II, Walker & Ni 2011) extrapolates over the
// last `depth` iterates: with f_i = g(x_i) - x_i,
//   gamma = argmin || f_k - sum_i gamma_i (f_{i+1} - f_i) ||_2,
//   x_{k+1} = g(x_k) - sum_i gamma_i (g_{i+1} - g_i),
// a GMRES-like step on the linearized fixed-point map that needs no Jacobian of R(F).
//
// Vectors are the finest level's interior variables (u faces and cell pressures) in the order
// of the co-rotated rows (CorotatedRows::target); the caller gathers and scatters them.
#include <Eigen/Core>
#include <deque>

namespace mgelastic::grid {

class AndersonMixing {
 public:
  explicit AndersonMixing(int depth) : m_depth(depth) {}
  // Records the pair (x, g(x)) and returns the next iterate (g(x) while the history is empty).
  Eigen::VectorXd mix(const Eigen::VectorXd& x, const Eigen::VectorXd& gx);
  // Forgets the history (after a rejected step or a change of the fixed-point map).
  void reset();
  int depth() const { return m_depth; }
  int history() const { return static_cast<int>(m_g.size()); }

 private:
  int m_depth;
  std::deque<Eigen::VectorXd> m_f, m_g;  // last depth + 1 residuals f_i and images g(x_i)
};

}  // namespace mgelastic::grid
