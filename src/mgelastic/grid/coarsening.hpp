#pragma once
// 2^d-to-1 coarsening of cell types (Sec. 6): a coarse cell is Dirichlet if any fine sub-cell is,
// otherwise interior if any sub-cell is interior, otherwise exterior. The coarse lattice has
// ceil(n/2) cells per axis, twice the cell size and the same origin.
#include <vector>

#include "mgelastic/grid/lattice.hpp"

namespace mgelastic::grid {

template <int Dim>
Lattice<Dim> coarsen(const Lattice<Dim>& fine);

template <int Dim>
std::vector<CellType> coarsen_cells(const Lattice<Dim>& fine, const std::vector<CellType>& cells);

}  // namespace mgelastic::grid
