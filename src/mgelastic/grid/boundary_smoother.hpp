#pragma once
// The boundary-band smoother of Sec. 5.3. Pre-multiplying L* by the substitution matrix U gives
// (12): the band momentum rows see the symmetric negative definite Schur complement
//   S = L_phi - G D_p^-1 G^T,
// relaxed here by point Gauss-Seidel. The band pressures are kept exact while u moves
// (p = D_p^-1 (b_p - G^T u)), so the Schur residual of a row equals its augmented residual.
// Interior variables outside the band act as Dirichlet values during these sweeps.
#include <cstdint>
#include <string>
#include <vector>

#include "mgelastic/grid/level.hpp"

namespace mgelastic::grid {

// Order of a call's sweeps. The band's rows are grouped into the colored blocks of the volume
// (Level::band_schedule); blocks of one color touch disjoint variables.
//   BAND_WIDE    sweep after sweep over the whole band, color by color (the paper's order).
//   BLOCK_LOCAL  color by color, each block takes all of the call's sweeps back to back while
//                its rows and lattice lines are in cache; the next color then sees its final
//                values. Every row relaxation is still an exact Gauss-Seidel step on the Schur
//                complement, in a fixed order, so the result does not depend on the thread
//                count. One sweep is the same in both orders.
// A band sweep is latency-bound on lattice lines read once per sweep (faces across x touch a
// line per lattice row for 3-4 of its values): BLOCK_LOCAL reads them once per call.
// AUTOMATIC (MultigridOptions' default) is BLOCK_LOCAL in 3D and BAND_WIDE in 2D, where a level's
// band stays in cache anyway and BLOCK_LOCAL cost rate on one misaligned clamp (80^2, nu 0.49:
// 0.292 -> 0.362; unchanged at 32-256^2 otherwise).
enum class BandSweepOrder { AUTOMATIC, BLOCK_LOCAL, BAND_WIDE };

// "auto", "block_local" or "band_wide" (the scene's solver.smoother_order); throws Error.
BandSweepOrder band_sweep_order(const std::string& name);

template <int Dim>
constexpr BandSweepOrder resolved(BandSweepOrder order) {
  if (order != BandSweepOrder::AUTOMATIC) return order;
  return Dim == 3 ? BandSweepOrder::BLOCK_LOCAL : BandSweepOrder::BAND_WIDE;
}

// The band rows' right-hand sides b - constant (BandKernel::rhs) that the sweeps read.
//   REFRESH  each call recomputes them from b (any caller, any time).
//   CURRENT  the caller refreshed them (refresh_band_rhs) since b last changed: the V-cycle does
//            once per visit of a level, whose b is fixed during the visit, so its six band calls
//            do not gather b at every band row six times.
enum class BandRhs { REFRESH, CURRENT };

// kernel.rhs[m] = b - constant of every band row m.
template <int Dim, typename Scalar>
void refresh_band_rhs(Level<Dim, Scalar>& level);

// Exact update of every band pressure from its (diagonal) pressure equation.
template <int Dim, typename Scalar>
void update_band_pressures(Level<Dim, Scalar>& level);

// `sweeps` forward Gauss-Seidel sweeps over the band momentum rows (all of them, or `subset`,
// indices into level.band_u), starting with an exact pressure update.
// A subset is relaxed serially, sweep after sweep.
template <int Dim, typename Scalar>
void band_gauss_seidel(Level<Dim, Scalar>& level, int sweeps,
                       const std::vector<std::uint32_t>* subset = nullptr,
                       BandSweepOrder order = BandSweepOrder::BAND_WIDE,
                       BandRhs rhs = BandRhs::REFRESH);
template <int Dim, typename Scalar>
void band_gauss_seidel(Level<Dim, Scalar>& level, int sweeps, BandSweepOrder order,
                       BandRhs rhs = BandRhs::REFRESH) {
  band_gauss_seidel(level, sweeps, nullptr, order, rhs);
}

// The same over the rows of a colored row schedule (Level::RowSchedule, e.g. the Fig. 8 rows),
// block by block in the schedule's order; the blocks of one color run in parallel.
template <int Dim, typename Scalar>
void band_gauss_seidel(Level<Dim, Scalar>& level, int sweeps,
                       const typename Level<Dim, Scalar>::RowSchedule& schedule,
                       BandSweepOrder order = BandSweepOrder::BAND_WIDE,
                       BandRhs rhs = BandRhs::REFRESH);

// Sets the traction boundary variables from the traction conditions: normal faces first, then
// the faces half a cell outside (Sec. 5.3), so every boundary condition holds exactly.
template <int Dim, typename Scalar>
void back_substitute_traction(Level<Dim, Scalar>& level);

}  // namespace mgelastic::grid
