#pragma once
// Where a level's residual sits: the squared residual of every row (stencil and band, all fields)
// summed over cubes of `block` cells of the lattice (by storage coordinates: the cube of cell s
// is s / block), the largest first, each as its share of the total. A slow mode of the V-cycle
// shows as a few cubes holding most of the residual after many cycles (the armadillo's under its
// feet, the bunny's in its ears: docs/notes/2026-12-06-variable-codes-and-embedded-slow-mode.md).
#include <array>
#include <cstddef>
#include <vector>

#include "mgelastic/grid/level.hpp"

namespace mgelastic::grid {

template <int Dim>
struct ResidualBlock {
  std::array<int, Dim> first;  // storage coordinates of the cube's first cell
  double share = 0;            // of the sum of squared residuals over the level
};

// The `count` cubes of `block`^Dim cells with the largest sums of squared residuals (fewer where
// fewer hold a nonzero residual), largest first; ties in coordinate order. Empty for a zero
// residual. The rows are evaluated lattice row by lattice row (no residual array): also for a
// float level whose cycle keeps none (local corrections, local_corrections.hpp).
template <int Dim, typename Scalar>
std::vector<ResidualBlock<Dim>> residual_blocks(const Level<Dim, Scalar>& level, int block,
                                                std::size_t count);

// The same sum of squared residuals split by field (u_0 .. u_{Dim-1}, p) and by where the row's
// variable sits: next to a Dirichlet cell (one of the variable's cells or a face neighbor of
// one is Dirichlet), else next to an exterior cell (the traction surface), else elsewhere.
// Each as its share of the total; all zero for a zero residual. A slow mode next to a clamp
// shows as next_to_dirichlet near 1 (the mixed box with a misaligned clamp:
// docs/notes/2026-12-06-misaligned-clamps.md).
template <int Dim>
struct ResidualShares {
  std::array<double, Dim + 1> field{};
  double next_to_dirichlet = 0, next_to_exterior = 0, elsewhere = 0;
};

template <int Dim>
ResidualShares<Dim> residual_shares(const Level<Dim, double>& level);

}  // namespace mgelastic::grid
