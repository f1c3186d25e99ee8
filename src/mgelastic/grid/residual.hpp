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
#include <cstdint>
#include <vector>

#include "mgelastic/grid/band_row_planes.hpp"
#include "mgelastic/grid/level.hpp"

namespace mgelastic::grid {

// Allocates level.r (zeros) where the level holds none: Multigrid's levels keep no r (the
// V-cycle restricts fresh residuals, residual_restriction.hpp, and the double solution level
// writes its residual into the float level's b), so whoever wants a residual array gets it here.
template <int Dim, typename Scalar>
void ensure_residual_storage(Level<Dim, Scalar>& level) {
  for (auto& field : level.r)
    if (field.size() != level.size()) assign_zeros_sparse(field, level.size(), level.live);
}

// Fills level.r (allocated if absent; no norm).
template <int Dim, typename Scalar>
void update_residual(Level<Dim, Scalar>& level);

// Fills level.r and returns the residual norm defined above.
template <int Dim, typename Scalar>
double compute_residual(Level<Dim, Scalar>& level);

// The residual norm above without a residual array (the rows evaluated chunk by chunk into
// scratch): residual_into's norm, bit for bit, for any thread count. Equal to compute_residual's
// up to the order of the sum. band_planes: band_row_planes(level) (its lines are evaluated
// run-wise, the same values), ignored when stale or null.
template <int Dim, typename Scalar>
double fresh_residual_norm(const Level<Dim, Scalar>& level,
                           const BandRowPlanes* band_planes = nullptr);

// The norm of the current level.r (as compute_residual returns it).
template <int Dim, typename Scalar>
double residual_norm(const Level<Dim, Scalar>& level);

// The residual of a double level written into other arrays (Dim + 1 of the lattice size), e.g.
// straight into the right-hand side of a float level (mixed-precision refinement), so the
// double level needs no r of its own. Values equal update_residual's, rounded once to Out;
// returns the norm above of the unrounded values (a residual beyond float range stays finite).
template <int Dim, typename Scalar, typename Out>
double residual_into(const Level<Dim, Scalar>& level, const std::array<Out*, Dim + 1>& r);

// The residual of the lattice planes [first, end) along the last axis (update_residual's values
// there, zeros included) written to r[f][k] for k in those planes only: r may point into a
// window of a few planes (residual_restriction.hpp). band_planes: band_row_planes(level).
template <int Dim, typename Scalar>
void residual_planes(const Level<Dim, Scalar>& level, const BandRowPlanes& band_planes, int first,
                     int end, const std::array<Scalar*, Dim + 1>& r);

// Residuals at chosen rows only (a local correction's box, local_correction.hpp), each the
// value update_residual writes there:
//   stencil_residual_at: every field's stencil row (zero where the field's equation is not a
//     stencil row) at the points of `stretches` (runs of flat indices along x), written to r[f]
//     stretch after stretch;
//   band_residual_at: out[i] for band momentum row rows[i] (BandKernel rows);
//   band_pressure_residual_at: out[i] for band pressure row rows[i] (band_p rows).
struct Stretch {
  std::ptrdiff_t first;
  std::uint32_t length;
};
template <int Dim, typename Scalar>
void stencil_residual_at(const Level<Dim, Scalar>& level, const std::vector<Stretch>& stretches,
                         const std::array<double*, Dim + 1>& r);
template <int Dim, typename Scalar>
void band_residual_at(const Level<Dim, Scalar>& level, const std::vector<std::uint32_t>& rows,
                      double* out);
template <int Dim, typename Scalar>
void band_pressure_residual_at(const Level<Dim, Scalar>& level,
                               const std::vector<std::uint32_t>& rows, double* out);

}  // namespace mgelastic::grid
