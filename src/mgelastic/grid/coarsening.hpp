#pragma once
// 2^d-to-1 coarsening of cell types (Sec. 6): a coarse cell is Dirichlet if any fine sub-cell is,
// otherwise interior if any sub-cell is interior, otherwise exterior. The coarse lattice has
// ceil(n/2) cells per axis, twice the cell size and the same origin.
//
// A thin part of the body coarsens into a sheet one coarse cell thick (no bending stiffness), and
// thick parts joined by a thin neck or a small contact patch into parts hinged at one coarse
// cell face or strip, which turn without strain (geometry/rigid_blocks.hpp); the fine level has
// neither. A coarsest level with a hinge is singular, and the correction of a coarse level is
// unbounded along it. repair_coarse_cells() makes coarse typings free of them, with the rule
// voxelize() applies to the finest.
#include <cstdint>
#include <vector>

#include "mgelastic/grid/lattice.hpp"

namespace mgelastic::grid {

template <int Dim>
Lattice<Dim> coarsen(const Lattice<Dim>& fine);

// ANY_CHILD: the paper's rule above. EVERY_CHILD: a coarse cell is Dirichlet only when every
// non-exterior child is, so a clamp top between coarse faces leaves the coarse cell free and
// the coarse level can correct the free fine cells inside it; the coarse problem is then softer
// than the fine one there, which only a Galerkin coarse operator makes up for
// (galerkin_coarsest.hpp; with the rediscretized operator the box at 63 cells diverges,
// docs/notes/2026-12-06-misaligned-clamps.md).
enum class CoarseDirichletRule { ANY_CHILD, EVERY_CHILD };

template <int Dim>
std::vector<CellType> coarsen_cells(const Lattice<Dim>& fine, const std::vector<CellType>& cells,
                                    CoarseDirichletRule rule = CoarseDirichletRule::ANY_CHILD);

// Where a coarse level's Dirichlet cells meet the finest level's Dirichlet wall, per cell and
// face (entry 2 Dim cell + 2 a + side; side 0 = lower, 1 = upper face along e_a; `factor` =
// coarse h / finest h): m + 1 when the finest wall lies m finest cells inside the coarse cell
// behind that face (the first finest layer from the face that holds a Dirichlet cell is all
// Dirichlet and is the m-th), 0 otherwise. Only there may a coarse level clamp at the finest
// level's depth (Level::dirichlet_zero_depth), m h_finest deeper than its own wall: a clamp top
// between coarse faces then acts where the finest one does, not up to 2^l - 1 finest cells higher.
// `misaligned` false: only faces that are finest walls (m = 0).
template <int Dim>
std::vector<std::uint8_t> finest_dirichlet_wall_layers(const Lattice<Dim>& finest,
                                                       const std::vector<CellType>& finest_cells,
                                                       const Lattice<Dim>& coarse,
                                                       const std::vector<CellType>& coarse_cells,
                                                       int factor, bool misaligned = true);

// Turns exterior real cells into interior ones until every non-exterior cell lies in a fully
// non-exterior 2^d block and the full blocks of each face-connected piece form one chain of
// blocks sharing 2^(d-1) x 1 halves (geometry::thicken_to_full_blocks, connect_full_blocks).
// The ghost ring stays exterior. Returns the number of cells added.
template <int Dim>
int repair_coarse_cells(const Lattice<Dim>& lattice, std::vector<CellType>& cells);

}  // namespace mgelastic::grid
