#pragma once
// Residual and restriction fused (issue 24 item 3): the V-cycle's step from level l to l + 1,
//   b_{l+1} = R (b_l - L x_l)   at coarse interior equations, x_{l+1} = 0,
// without a residual array r_l. Coarse planes (normal to the last axis) are taken in blocks;
// coarse plane z reads the fine residual of fine planes 2 z - 2 .. 2 z (transfer.hpp's taps),
// which are computed into a window of three planes per field (residual_planes) that slides by
// two planes: each fine plane's residual is computed once (once more at a block's start) and read
// from cache. The values are those of update_residual followed by restrict_residual, bit for bit,
// for any thread count (every residual row and every restriction sum is the same expression).
// Memory: no r on the levels (only the window, 3 planes x (Dim + 1) fields per thread);
// traffic: r is neither written nor read back.
#include <vector>

#include "mgelastic/grid/band_row_planes.hpp"
#include "mgelastic/grid/level.hpp"

namespace mgelastic::grid {

// Per-thread windows, kept between calls (reallocating them would page-fault every cycle).
template <typename Scalar>
struct ResidualWindows {
  std::vector<std::vector<Scalar>> thread;
  std::size_t bytes() const;
};

// band_planes = band_row_planes(fine), current for fine's band rows.
template <int Dim, typename Scalar>
void restrict_fresh_residual(const Level<Dim, Scalar>& fine, const BandRowPlanes& band_planes,
                             Level<Dim, Scalar>& coarse, ResidualWindows<Scalar>& windows);

}  // namespace mgelastic::grid
