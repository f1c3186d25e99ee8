#pragma once
// The boundary-band smoother of Sec. 5.3. Pre-multiplying L* by the substitution matrix U gives
// (12): the band momentum rows see the symmetric negative definite Schur complement
//   S = L_phi - G D_p^-1 G^T,
// relaxed here by point Gauss-Seidel. The band pressures are kept exact while u moves
// (p = D_p^-1 (b_p - G^T u)), so the Schur residual of a row equals its augmented residual.
// Interior variables outside the band act as Dirichlet values during these sweeps.
#include <cstdint>
#include <vector>

#include "mgelastic/grid/level.hpp"

namespace mgelastic::grid {

// Exact update of every band pressure from its (diagonal) pressure equation.
template <int Dim, typename Scalar>
void update_band_pressures(Level<Dim, Scalar>& level);

// `sweeps` forward Gauss-Seidel sweeps over the band momentum rows (all of them, or `subset`,
// indices into level.band_u), starting with an exact pressure update.
template <int Dim, typename Scalar>
void band_gauss_seidel(Level<Dim, Scalar>& level, int sweeps,
                       const std::vector<std::uint32_t>* subset = nullptr);

// The same over the rows of a colored row schedule (Level::RowSchedule, e.g. the Fig. 8 rows),
// block by block in the schedule's order; the blocks of one color run in parallel.
template <int Dim, typename Scalar>
void band_gauss_seidel(Level<Dim, Scalar>& level, int sweeps,
                       const typename Level<Dim, Scalar>::RowSchedule& schedule);

// Sets the traction boundary variables from the traction conditions: normal faces first, then
// the faces half a cell outside (Sec. 5.3), so every boundary condition holds exactly.
template <int Dim, typename Scalar>
void back_substitute_traction(Level<Dim, Scalar>& level);

}  // namespace mgelastic::grid
