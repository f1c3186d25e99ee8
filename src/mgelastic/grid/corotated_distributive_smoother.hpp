#pragma once
// Distributive Gauss-Seidel for the interior of the quasi-linear co-rotated system (Zhu et al.
// 2010, Sec. 7, Eqs. 14-16), the R != I generalization of distributive_smoother.hpp.
//
// System (rows of corotated_operator.hpp, rotations frozen): L = [L_uu, L_up; L_pu, D_p] with
// L_up ~ -mu (div R^T)^T (momentum rows' pressure terms, R_ij p edge-averaged), L_pu ~
// mu (R grad)^T (pressure rows' gradient terms) and D_p = mu^2 / lambda. Distribution matrix
//   M = [ I            -(div R^T)^T ]   discretized as   M = [ I          L_up / mu            ]
//       [ (R grad)^T   -2 Lap + c/mu ]                       [ L_pu / mu  -2 Lap_h + c/mu (p) ]
// i.e. the off-diagonal blocks are the rows' own coupling terms over mu, so that at R = I this
// is exactly the linear distribution (6) with the Sec. 8 inertia term. The paper's (15) has a
// zero lower-left block because its momentum block is 2 mu Lap (the PAPER stress); the engine's
// default SYMMETRIZED stress has the linear mu (Lap + grad div) block at R = I, whose grad div
// part the (R grad)^T block cancels: for a constant R, L M = [mu Lap - c, 0; ., -mu (1 + 2 mu /
// lambda) Lap + .] (lower triangular, Laplacian diagonal); with varying R the upper-right block
// is O(grad R), small near a solution (the paper's argument after (16)).
//
// A step on row m (target variable t): r = b_t - constant_m - L_m . x, delta = r / (LM)_mm,
// x += delta * M e_m. (LM)_mm = L_m . M e_m is computed from the stored rows, so it is exact at
// Dirichlet neighbours (the distribution moves unknowns only; the linear smoother's restricted
// q step) and for any R. Rows visited: those the linear level marks DISTRIBUTIVE (Relaxation),
// u_1, .., u_d, then p (the order Algorithm 2 requires), each field over the level's 8-colour
// (4 in 2D) block partition: blocks of one colour run in parallel (their distance exceeds the
// rows' reach of 2 cells plus the distribution's 1), lexicographic inside a block, so results do
// not depend on the thread count. At lambda = 0 the pressure rows read p = 0 and are skipped.
//
// Data: per row of CorotatedRows, a CSR list of (global variable, weight) = column m of M
// restricted to unknowns, and 1 / (LM)_mm (0: row not relaxed here). Double precision only.
#include <cstdint>
#include <vector>

#include "mgelastic/grid/corotated_operator.hpp"
#include "mgelastic/grid/level.hpp"

namespace mgelastic::grid {

template <int Dim>
class CorotatedDistributiveSmoother {
 public:
  // `rows`: the level's frozen co-rotated rows; the smoother keeps no reference to them.
  CorotatedDistributiveSmoother(const Level<Dim, double>& level, const CorotatedRows& rows);

  // One sweep over the distributive rows of `level` (the rows passed to the constructor).
  void sweep(Level<Dim, double>& level, const CorotatedRows& rows) const;

  // Rows relaxed distributively (diagnostics and tests).
  std::size_t relaxed_rows() const { return m_relaxed; }

 private:
  void build_distribution(const Level<Dim, double>& level, const CorotatedRows& rows);
  void build_diagonal(const Level<Dim, double>& level, const CorotatedRows& rows);

  std::vector<std::uint32_t> m_start{0};
  std::vector<std::uint32_t> m_variable;
  std::vector<double> m_weight;
  std::vector<double> m_inverse_diagonal;
  std::size_t m_relaxed = 0;
};

}  // namespace mgelastic::grid
