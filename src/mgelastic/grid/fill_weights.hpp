#pragma once
// Fill weights of coarse cells: the fraction of a coarse cell's volume that the finest level's
// body occupies (mean of its 2^d children's weights; a fine body cell has weight 1, an exterior
// child or a child beyond the fine lattice 0).
//
// Why: Sec. 6 types a coarse cell interior when any child is, so a thin part of the body becomes
// up to one coarse cell (two fine cells) thicker on the coarse level, with a bending stiffness
// many times the fine level's; the coarse correction of its deformation then falls short and
// the V-cycle slows down on scans with ears and limbs (docs/embedded-geometry.md). Scaling each
// coarse cell's stresses by its fill weight (explicit_rows.hpp) keeps the coarse stiffness close
// to the fine one. Cells that repair_coarse_cells() added (no body child) get the smallest
// weight of a partly filled cell, 1 / 2^d, so the repair keeps them stiff enough to remove the
// strain-free modes it targets.
//
// Layout: one weight per storage point of the coarse lattice (lattice.hpp), 0 for exterior and
// ghost cells, 1 for Dirichlet cells.
#include <vector>

#include "mgelastic/grid/lattice.hpp"

namespace mgelastic::grid {

// `fine_weights` empty means every non-exterior fine cell has weight 1 (the finest level).
template <int Dim>
std::vector<double> coarse_fill_weights(const Lattice<Dim>& fine,
                                        const std::vector<CellType>& fine_cells,
                                        const std::vector<double>& fine_weights,
                                        const Lattice<Dim>& coarse,
                                        const std::vector<CellType>& coarse_cells);

// True when every non-exterior cell has weight 1 (the level needs no weighted rows).
bool all_full(const std::vector<double>& weights, const std::vector<CellType>& cells);

}  // namespace mgelastic::grid
