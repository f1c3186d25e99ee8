#pragma once
// Quasi-linear co-rotational operator (Zhu et al. 2010, Sec. 7, Eq. 14) on one level, with the
// per-cell rotations R frozen, in the engine's displacement form (F = I + G, G = grad u).
// With the pressure p = -(lambda/mu) tr(R^T F - I) the stress (13) is
//   P = 2 mu G + 2 mu (I - R) - mu p R     (CorotatedStress::PAPER, the paper's form), or, equal
//   wherever R^T F is symmetric, P = mu (G + R G^T R) + mu (I - R)^2 - mu p R (SYMMETRIZED, the
//   default: the linear rows at R = I),
// and the equations, written in divergence form like the band rows (explicit_rows.hpp), are
//   momentum row of u_i at face k:  sum_j [P_ij(k + e_j/2) - P_ij(k - e_j/2)] / h - c u_i = b
//   pressure row at cell k:         mu R_ij G_ij + (mu^2/lambda) p - mu (d - tr R)     = b
// P_ii lives at cell centers (R_ii and p of the cell); P_ij (i != j) at the (i, j) edges, where
// R_ij p and R_ij are averaged over the edge's interior cells (Sec. 7: edge-centred pressures).
// In the pressure row G_ii is the cell's own difference and G_ij (i != j) the mean over the
// four surrounding edges whose two u_i faces are interior or Dirichlet variables.
// Boundary stresses (an exterior cell at the stress location) take their traction value; a
// traction gradient G_ii in a pressure row is eliminated with P_ii = sigma (as Sec. 5.3).
// PAPER at R = I is 2 mu Lap u + lambda grad div u, not the linear engine's mu (Lap + grad div)
// u + lambda grad div u (they agree where grad u is symmetric); SYMMETRIZED at R = I is the
// linear operator. `material.model: linear` never uses these rows.
//
// Rows cover every interior variable (u faces and cell pressures): the co-rotated smoother is
// a box (Vanka) smoother on these rows, not the distributive/band split of the linear engine.
// "homogeneous" rows (coarse levels: correction equations) drop every constant (tractions,
// 2 mu (I - R), mu (d - tr R)). At lambda = 0 the pressure row is p = 0.
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "mgelastic/grid/corotation.hpp"
#include "mgelastic/grid/level.hpp"

namespace mgelastic::grid {

// Momentum-row stress at interior stress locations. PAPER: (13) as written, 2 mu (F - R) + ...,
// whose frozen form penalizes skew(R^T F): each refresh moves a slender body's bending rotation
// only a little (tests/grid/test_corotated_multigrid.cpp measures it). SYMMETRIZED: the same
// co-rotated stress written mu R (R^T F + F^T R - 2 I) - mu p R, frozen as
// mu (G + R G^T R) + mu (I - R)^2 - mu p R with every gradient averaged to the stress location
// (known faces only); it equals the linear rows at R = I and PAPER wherever R^T F is symmetric,
// so both have the same fixed point (boundary elimination and pressure rows are shared).
enum class CorotatedStress { SYMMETRIZED, PAPER };

// CSR rows over global variable indices (field * lattice.size() + k, level.hpp); equation
// row . x + constant = b at the row's target variable.
struct CorotatedRows {
  std::vector<std::uint32_t> target;
  std::vector<std::uint32_t> start{0};
  std::vector<std::uint32_t> column;
  std::vector<double> value;
  std::vector<double> constant;
  std::vector<std::int32_t> row_of;  // global variable -> row index, -1 for non-unknowns
  std::size_t rows() const { return target.size(); }
  double coefficient(std::size_t row, std::uint32_t variable) const;
};

template <int Dim>
CorotatedRows build_corotated_rows(const Level<Dim, double>& level,
                                   const std::vector<Matrix<Dim>>& rotations,
                                   const BoundaryStress<Dim>& sigma, bool homogeneous,
                                   CorotatedStress form = CorotatedStress::SYMMETRIZED);

// The same into `rows`, reusing its storage (a refresh rebuilds every level's rows).
template <int Dim>
void build_corotated_rows(const Level<Dim, double>& level,
                          const std::vector<Matrix<Dim>>& rotations,
                          const BoundaryStress<Dim>& sigma, bool homogeneous, CorotatedStress form,
                          CorotatedRows& rows);

// r = b - constant - row . x at every row's variable (0 elsewhere) into level.r; returns the
// 2-norm over all rows (pressure rows only when lambda > 0).
template <int Dim>
double corotated_residual(Level<Dim, double>& level, const CorotatedRows& rows);

// What the matrix-free residual below keeps between calls on one level (pass the same scratch
// only with the same level): the stresses at every location (Dim^2 arrays over the lattice,
// written at the same locations on every call) and the rows' targets.
template <int Dim>
struct CorotatedResidualScratch {
  std::array<FieldArray<double>, Dim * Dim> stress;
  std::vector<std::uint32_t> targets;
};

// The same residual for the rows build_corotated_rows(level, rotations, ...) would give, each
// row applied as it is built (no stored rows: the non-linear residual between refreshes).
template <int Dim>
double corotated_residual(Level<Dim, double>& level, const std::vector<Matrix<Dim>>& rotations,
                          const BoundaryStress<Dim>& sigma, bool homogeneous,
                          CorotatedStress form = CorotatedStress::SYMMETRIZED,
                          CorotatedResidualScratch<Dim>* scratch = nullptr);

// The stress the momentum rows of `rotations` (non-homogeneous) add at one location for the
// level's current x: P_ii at cell `location` (j == i) or P_ij at the (i, j) edge `location`.
// std::nullopt where the rows add no stress of x there: a boundary stress (an exterior cell at
// the location: the rows take its traction value, a load) or an edge between Dirichlet cells.
// For the reactions of constraints (constraint_reactions.hpp).
template <int Dim>
std::optional<double> corotated_stress(const Level<Dim, double>& level,
                                       const std::vector<Matrix<Dim>>& rotations,
                                       const BoundaryStress<Dim>& sigma, int i, int j,
                                       std::ptrdiff_t location,
                                       CorotatedStress form = CorotatedStress::SYMMETRIZED);

// Sets the traction variables from the co-rotated traction conditions (P_ii = sigma at normal
// faces, P_ij = sigma at the faces half a cell outside), the rules of level.traction with the
// co-rotated stress; homogeneous drops sigma and the R-only terms (coarse corrections).
template <int Dim>
void corotated_back_substitute(Level<Dim, double>& level, const std::vector<Matrix<Dim>>& rotations,
                               const BoundaryStress<Dim>& sigma, bool homogeneous);

}  // namespace mgelastic::grid
