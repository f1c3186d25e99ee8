#pragma once
// Residual r = b - L* x of the augmented system on one level: uniform stencils (stencil.hpp)
// for distributively smoothed equations, stored rows for the boundary band. Entries of r at
// locations without an equation are zero, so restriction can read r everywhere.
//
// Reported norm: the 2-norm of the residual of the symmetric augmented system (5) as written,
// sqrt(sum r_u^2 + sum r_p^2), momentum rows mu (Lap + grad div) u - mu grad p = -f and pressure
// rows mu div u + (mu^2/lambda) p = 0. At lambda = 0 the pressure is eliminated exactly (p = 0)
// and its rows do not count.
// Dynamics steps (Sec. 8) add -c u to every momentum row (Level::inertia).
#include <array>
#include <cstddef>

#include "mgelastic/grid/level.hpp"

namespace mgelastic::grid {

// Fills level.r (the V-cycle's restriction reads it; no norm).
template <int Dim, typename Scalar>
void update_residual(Level<Dim, Scalar>& level);

// Fills level.r and returns the residual norm defined above.
template <int Dim, typename Scalar>
double compute_residual(Level<Dim, Scalar>& level);

// The norm of the current level.r (as compute_residual returns it).
template <int Dim, typename Scalar>
double residual_norm(const Level<Dim, Scalar>& level);

// The residual of a double level written into other arrays (Dim + 1 of the lattice size), e.g.
// straight into the right-hand side of a float level (mixed-precision refinement), so the
// double level needs no r of its own. Values equal update_residual's, rounded once to Out;
// returns the norm above of the unrounded values (a residual beyond float range stays finite).
template <int Dim, typename Scalar, typename Out>
double residual_into(const Level<Dim, Scalar>& level, const std::array<Out*, Dim + 1>& r);

}  // namespace mgelastic::grid
