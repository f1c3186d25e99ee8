#pragma once
// Inter-grid transfers of Sec. 6, tensor products of the 1D averaging operators
//   B1 u[x] = (u[x-h/2] + u[x+h/2]) / 2
//   B2 u[x] = (u[x-h] + 2 u[x] + u[x+h]) / 4
//   B3 u[x] = (u[x-3h/2] + 3 u[x-h/2] + 3 u[x+h/2] + u[x+3h/2]) / 8
// per variable: R_i = B2 along e_i, B1 along the others; P_i^T = 2^d (B2 along e_i, B3 along
// the others); R_p = B1 in every direction, P_p^T = 2^d B1 (piecewise constant).
// Restriction writes coarse right-hand sides only at coarse interior equations (coarse boundary
// conditions are homogeneous) and zeroes the coarse unknowns. Prolongation adds the correction
// to fine interior variables, renormalizing the weights over coarse variables that are defined
// (interior, Dirichlet = 0, or back-substituted traction values); inactive ones are skipped.
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "mgelastic/grid/level.hpp"

namespace mgelastic::grid {

template <int Dim, typename Scalar>
void restrict_residual(const Level<Dim, Scalar>& fine, Level<Dim, Scalar>& coarse);

// The restriction of the coarse planes [first, end) along the last axis only (no zeroing):
// r[f] is the fine residual of field f, indexable at the fine planes 2 first - 2 .. 2 end - 2
// (the taps of those coarse planes), e.g. a window of residual_planes (residual_restriction.hpp).
template <int Dim, typename Scalar>
void restrict_residual_planes(const Level<Dim, Scalar>& fine,
                              const std::array<const Scalar*, Dim + 1>& r,
                              Level<Dim, Scalar>& coarse, int first, int end);

template <int Dim, typename Scalar>
void prolongate_correction(const Level<Dim, Scalar>& coarse, Level<Dim, Scalar>& fine);

// A linear combination of a level's variables: (global index, weight) terms.
struct LinearCombination {
  std::vector<std::pair<std::uint32_t, double>> terms;
};

// Sorts the terms by variable and adds up repeated ones (dropping those that cancel to zero).
void merge_terms(LinearCombination& combination);

// The row of prolongate_correction for the fine u_field variable at flat index k: the coarse
// variables it reads (interior or traction, as global coarse indices; Dirichlet ones read zero)
// with their weights, merged. Empty for a fine variable that is not INTERIOR (the prolongation
// writes only those). The Galerkin band rows (galerkin_band_rows.hpp) are built from it.
template <int Dim, typename Scalar>
LinearCombination prolongation_row(const Level<Dim, Scalar>& coarse, const Level<Dim, Scalar>& fine,
                                   int field, std::ptrdiff_t k);

}  // namespace mgelastic::grid
