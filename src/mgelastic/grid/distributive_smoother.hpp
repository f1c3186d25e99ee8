#pragma once
// Distributive Gauss-Seidel for the interior of the augmented system (Sec. 4.2, Algorithm 2).
// With the distribution matrix M = [I, -grad; div, -2 Lap] the composed operator
//   L M = [mu Lap I, 0; mu (1 + mu/lambda) div, -mu (1 + 2 mu/lambda) Lap]
// is lower triangular with Laplacian diagonal blocks, so point Gauss-Seidel on L M v = b works
// for any Poisson ratio. A step on equation i computes its residual r_i, delta = r_i / (LM)_ii,
// and adds delta times column i of M to (u, p):
//   psi_i at face k:  u_i[k] += delta,  p[k] -= delta/h,  p[k - s_i] += delta/h;
//                     (LM)_ii = -2 d mu / h^2
//   q at cell k:      u_i[k + s_i] += delta/h,  u_i[k] -= delta/h  (all i),
//                     p[k] += 4 d delta / h^2,  p[k +- s_j] -= 2 delta / h^2;
//                     (LM)_pp = mu (1 + 2 mu/lambda) 2 d / h^2
// A sweep visits the colored blocks (Sec. 9.4; colors in turn, the blocks of one color in
// parallel) and relaxes in each block u_1, u_2, (u_3), then p, in this exact order, over equations
// marked DISTRIBUTIVE. Block by block rather than field by field over the level: a block's fields
// (whole lattice rows, up to ~16 Ki cells, ~560 KB in float) stay in cache through its four passes,
// so the sweep reads x, b and the relaxation codes from memory once instead of once per pass. The
// psi rows do not see q steps (L M is lower triangular), so only a block's q rows at its border
// read neighbours that the field-by-field order would have relaxed further. Dynamics (Sec. 8): with
// the inertia term the momentum rows read L_i - c u_i and the distribution's pressure block becomes
// -2 Lap + c/mu, which keeps L M lower triangular:
//   (LM)_ii = -2 d mu / h^2 - c,   q step: p[k] += (4 d / h^2 + c / mu) delta,
//   (LM)_pp = mu (1 + 2 mu/lambda) 2 d / h^2 + c mu / lambda.
#include "mgelastic/grid/level.hpp"

namespace mgelastic::grid {

template <int Dim, typename Scalar>
void distributive_sweep(Level<Dim, Scalar>& level);

}  // namespace mgelastic::grid
