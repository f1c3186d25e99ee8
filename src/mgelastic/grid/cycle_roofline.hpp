#pragma once
// Roofline model of a V-cycle: the bytes each phase of Multigrid::vcycle() must move between
// memory and the cores, per cycle, summed over the levels the cycle visits (a W-cycle visits
// coarse levels more often). Judge a phase by model bytes / its seconds against the STREAM triad
// bandwidth measured in the same run (core/stream_triad.hpp, docs/performance.md).
//
// Conventions: S = sizeof(Scalar) of the level (double for the mixed-precision solution level),
// F = Dim + 1 fields, n = lattice.size() (padded lattice), c = real cells (the distributive
// sweep's blocks cover only these). A whole-array pass counts each array it reads once and each
// array it writes once more (read-modify-write = 2 passes); stencil neighbours come from cache.
// Band rows are scattered: their stored indices and coefficients are counted per row, values at
// a row's stencil entries are assumed cached (neighbouring rows share them), its own variable,
// right-hand side and eliminated pressures are counted per row.
//   interior_smoothing  per smoothing, per momentum field i: read x (F), b_i, relaxation_i;
//                       write u_i, p; pressure: read x (F), b_p, relaxation_p, cells; write x (F)
//   boundary_smoothing  per band_gauss_seidel call: the band pressure update (compact rows,
//                       Level::band_p_kernel: pattern and target 8, inverse and constant and b
//                       3S, p write S; their patterns cached),
//                       the right-hand side refresh (band_u rows: index 5, constant and b read,
//                       rhs write: 3S), per sweep per row: pattern, target, field (9), rhs S,
//                       own variable read + write 2S, each eliminated pressure read + write 2S
//                       (block-local order: the first sweep only, the later ones hit cache);
//                       two full calls per smoothing plus the traction back-substitution (rule
//                       records and 4 S per rule); the two Fig. 8 relocation calls per level visit
//                       over their row subsets (the pressure update is still the full band_p)
//   residual            read x, b (F S each), relaxation (F), write r (F S) over n; band rows:
//                       index 9, constant, b, r (3S); pressure rows: pattern and target 8,
//                       constant, b, r, own p, extra diagonal (5S)
//   restriction         read fine r (F S n_f); coarse: zero x and b (2 F S n_c), read kind (F)
//                       fused (Multigrid::fuses_restriction, residual_restriction.hpp): counted
//                       with the residual, which then writes no r (the window stays in cache)
//                       but the coarse x, b and kind above; restriction moves nothing
//   prolongation        read coarse x and kind (F (S + 1) n_c); fine kind (F n_f), read + write
//                       fine x (2 F S n_f)
//   coarse_solve        the Cholesky factor twice (forward and backward substitution), coarse b
//                       read and x written (2 F S n_c), kind (F n_c)
//   refinement          mixed precision only: read r (8 F n), write float b, x (2 F S n); then
//                       read kind, e, x and write x (F (1 + S + 16) n), traction back-substitution
//   cycle_residual      a residual of the solution level plus the norm's read of r (F S n);
//                       single precision: the finest level's rows without r (no write, no read)
//   (mixed precision refines only on some cycles, MultigridOptions::refinement_reduction:
//   cycle_roofline scales refinement and the double residual by refinements per cycle and adds
//   the float norms of the other cycles, counted as in single precision)
//   solve_setup         per SOLVE, not per cycle: one residual and norm of the solution level and
//                       the copy of its x (read + write 2 * 8 F n)
#include <cstddef>
#include <string>
#include <vector>

#include "mgelastic/grid/multigrid.hpp"

namespace mgelastic::grid {

// Bytes per phase of one cycle of `mg` (solve_setup: of one solve). PhaseSeconds holds bytes.
template <int Dim, typename Scalar>
PhaseSeconds cycle_bytes(const Multigrid<Dim, Scalar>& mg);

// One row of the roofline table: per cycle.
struct PhaseRoofline {
  std::string name;
  double seconds = 0, bytes = 0, gb_per_s = 0, triad_fraction = 0;
};
struct CycleRoofline {
  double triad_gb_per_s = 0;
  std::vector<PhaseRoofline> phases;  // PhaseSeconds order; solve_setup spread over the cycles
  PhaseRoofline total;                // the whole cycle: solve seconds / cycles, all bytes
  double unattributed_seconds = 0;    // cycle seconds not inside any phase's timer
};

// Seconds per cycle from mg.phase_seconds() and `report` (the solve they were measured in;
// the timers must have started at zero before it), bytes from cycle_bytes.
template <int Dim, typename Scalar>
CycleRoofline cycle_roofline(const Multigrid<Dim, Scalar>& mg, const SolveReport& report,
                             double triad_gb_per_s);

// The terms above for one level, each for one call of the phase's kernel.
template <int Dim, typename Scalar>
double distributive_sweep_bytes(const Level<Dim, Scalar>& level);
template <int Dim, typename Scalar>
double band_gauss_seidel_bytes(const Level<Dim, Scalar>& level, int sweeps);
template <int Dim, typename Scalar>
double residual_bytes(const Level<Dim, Scalar>& level);
template <int Dim, typename Scalar>
double restriction_bytes(const Level<Dim, Scalar>& fine, const Level<Dim, Scalar>& coarse);
template <int Dim, typename Scalar>
double fused_residual_restriction_bytes(const Level<Dim, Scalar>& fine,
                                        const Level<Dim, Scalar>& coarse);
template <int Dim, typename Scalar>
double prolongation_bytes(const Level<Dim, Scalar>& coarse, const Level<Dim, Scalar>& fine);

}  // namespace mgelastic::grid
