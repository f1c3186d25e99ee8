#pragma once
// The non-augmented (displacement-only) system of a level, assembled explicitly:
//   S u = c,  S = L_phi - G D_p^-1 G^T  (Eq. 12, upper-left block),
// the staggered finite-difference discretization of Eq. 3 with the same boundary treatment as
// the augmented system. S is symmetric negative definite; we store A = -S (SPD) for Cholesky and
// CG. Unknowns are the level's interior u variables, in the order of `u_variables`. On a level
// with Galerkin band rows (Level::galerkin_band_rows) those rows are read from band_u, and A is
// then not exactly symmetric (the coarse solver factors it by LU).
// Used for the exact solve on the coarsest level and by the CG baseline (Fig. 11).
#include <Eigen/Sparse>
#include <cstdint>
#include <vector>

#include "mgelastic/grid/level.hpp"

namespace mgelastic::grid {

template <int Dim>
struct NonAugmentedSystem {
  Eigen::SparseMatrix<double> matrix;         // A = -S, SPD
  Eigen::SparseMatrix<double> coupling;       // G: (u unknowns) x (pressures)
  Eigen::VectorXd inverse_pressure_diagonal;  // D_p^-1 (zero at lambda = 0)
  // Fill weight w of each pressure's cell (fill_weights.hpp): `coupling` holds the momentum rows'
  // pressure coefficients G W, the pressure rows read G^T, so G D_p^-1 G^T above is
  // coupling (W D_p)^-1 coupling^T. Ones on the finest level.
  Eigen::VectorXd pressure_weight;
  std::vector<std::uint32_t> u_variables, p_variables;  // global indices on the level
  Eigen::VectorXd u_constant, p_constant;  // boundary stresses and Dirichlet values moved right

  // Right-hand side of A u = rhs from the level's b (reads b at the unknowns).
  template <typename Scalar>
  Eigen::VectorXd right_hand_side(const Level<Dim, Scalar>& level) const;
  // Writes u, the exact pressures p = D^-1 (b_p - G^T u), into the level.
  template <typename Scalar>
  void scatter(const Eigen::VectorXd& u, Level<Dim, Scalar>& level) const;
};

// Assembles the system from the level's classification; Dirichlet values are read from level.x.
template <int Dim, typename Scalar>
NonAugmentedSystem<Dim> assemble_nonaugmented(const Level<Dim, Scalar>& level,
                                              const BoundaryStress<Dim>& sigma);

}  // namespace mgelastic::grid
