#pragma once
// Galerkin displacement rows for a coarse level's boundary band:
//   A_c[I, J] = (P^T A_f P)[I, J] / 2^d      for I a band momentum row, J a displacement,
// with P the V-cycle's prolongation of displacement corrections (prolongation_row, after the
// coarse traction back-substitution, whose pressure terms are left out) and A_f the fine level's
// momentum rows (its band rows, else RowBuilder's rows, which equal the stencils). The coarse
// rows keep their own pressure terms, so the band's pressure elimination (one diagonal pressure
// row per band cell, up to two pressures per momentum row) is unchanged; the 2^d matches the
// V-cycle's restricted right-hand side (P^T = 2^d R in the interior).
//
// Why: a rediscretized coarse band misrepresents the staircase surface and a clamp top between
// coarse faces, and the V-cycle then stalls at 0.55-0.78 per cycle on embedded bodies
// (docs/notes/2026-12-06-misaligned-clamps.md); these rows give two-level rates of 0.25-0.34.
//
// Computed locally: P rows only for the fine variables within a few coarse cells of the band,
// fine rows only where P meets the band. Setup cost and memory are proportional to the band.
//
// On a smoothed level the rows next to a Dirichlet cell keep their rediscretized terms: with
// Galerkin rows there the distributive sweeps and the band sweeps drive each other up and the
// smoothing diverges (a 32^3 box's level 1: the residual x2-4 per pass, the largest in the
// tangential rows beside the clamp; docs/notes/2026-12-06-galerkin-band-rows.md).
#include <string>
#include <vector>

#include "mgelastic/grid/explicit_rows.hpp"
#include "mgelastic/grid/level.hpp"

namespace mgelastic::grid {

// Which coarse levels' band rows are Galerkin rows (MultigridOptions::coarse_band_rows):
// none (the paper's rediscretized rows), the coarsest level's, or every coarse level's.
enum class CoarseBandRows { REDISCRETIZED, GALERKIN_COARSEST, GALERKIN };

// "rediscretized", "galerkin_coarsest" or "galerkin"; throws Error naming `pointer` otherwise.
CoarseBandRows coarse_band_rows(const std::string& name, const std::string& pointer);

// Per row of coarse.band_u: the Galerkin displacement terms (interior coarse displacements,
// global indices, sorted); empty for the rows `wanted` (if given) leaves out. Both levels need
// their CSR band rows (before drop_band_csr).
template <int Dim, typename Scalar>
std::vector<std::vector<RowTerm>> galerkin_band_displacement_terms(
    const Level<Dim, Scalar>& fine, const Level<Dim, Scalar>& coarse,
    const std::vector<char>* wanted = nullptr);

// Which band rows of a level take Galerkin terms: all (the coarsest level, solved exactly), or
// all but those with a Dirichlet cell among their two cells' neighbors (a smoothed level).
enum class GalerkinRowSet { ALL, AWAY_FROM_DIRICHLET };

// Replaces the displacement terms of the chosen rows of coarse.band_u by the Galerkin terms,
// updates the Schur diagonal and rebuilds the sweeps' data (rebuild_band_sweep_data); sets
// galerkin_band_rows.
template <int Dim, typename Scalar>
void install_galerkin_band_rows(const Level<Dim, Scalar>& fine, Level<Dim, Scalar>& coarse,
                                GalerkinRowSet set);

}  // namespace mgelastic::grid
