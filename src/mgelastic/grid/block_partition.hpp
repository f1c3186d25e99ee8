#pragma once
// Colored rectangular blocks for multithreaded Gauss-Seidel (Sec. 9.4, Fig. 19): the real cells
// of a lattice are cut into blocks (whole lattice rows along x, 4-16 rows along y, 2-8 layers
// along z; 16 x 16 in 2D) and each block gets the color given by the parity of its block index
// along every axis, 2^d colors. Two blocks of one color are at least one block apart, wider than
// any stencil's reach (2 cells), so blocks of one color are relaxed concurrently without locks. The
// traversal order is fixed, so results do not depend on the thread count.
#include <array>
#include <vector>

#include "mgelastic/grid/lattice.hpp"

namespace mgelastic::grid {

template <int Dim>
struct Block {
  IVec<Dim> lo, hi;  // stored coordinates, half-open [lo, hi)
};

template <int Dim>
struct BlockPartition {
  static constexpr int color_count = 1 << Dim;
  std::array<std::vector<Block<Dim>>, color_count> colors;
  IVec<Dim> blocks_per_axis;
  IVec<Dim> block_size;

  // Color and index (within its color) of the block containing stored coordinates s.
  int color_of(const IVec<Dim>& s) const;
};

// The block shape for a lattice (block_partition.cpp says why).
template <int Dim>
IVec<Dim> default_block_size(const Lattice<Dim>& lattice);

template <int Dim>
BlockPartition<Dim> partition_into_blocks(const Lattice<Dim>& lattice, const IVec<Dim>& block_size);
template <int Dim>
BlockPartition<Dim> partition_into_blocks(const Lattice<Dim>& lattice) {
  return partition_into_blocks(lattice, default_block_size(lattice));
}

// Calls f(k) for every flat index of the block in lexicographic order (x fastest).
template <int Dim, typename F>
void for_each_in_block(const Lattice<Dim>& lattice, const Block<Dim>& block, F&& f) {
  if constexpr (Dim == 2) {
    for (int y = block.lo[1]; y < block.hi[1]; ++y) {
      const std::ptrdiff_t row = lattice.index(IVec<2>(0, y));
      for (int x = block.lo[0]; x < block.hi[0]; ++x) f(row + x);
    }
  } else {
    for (int z = block.lo[2]; z < block.hi[2]; ++z)
      for (int y = block.lo[1]; y < block.hi[1]; ++y) {
        const std::ptrdiff_t row = lattice.index(IVec<3>(0, y, z));
        for (int x = block.lo[0]; x < block.hi[0]; ++x) f(row + x);
      }
  }
}

// Calls f(k, n) for every x-row segment of the block: flat index of its first point, length.
template <int Dim, typename F>
void for_each_row_in_block(const Lattice<Dim>& lattice, const Block<Dim>& block, F&& f) {
  const int length = block.hi[0] - block.lo[0];
  if constexpr (Dim == 2) {
    for (int y = block.lo[1]; y < block.hi[1]; ++y)
      f(lattice.index(IVec<2>(block.lo[0], y)), length);
  } else {
    for (int z = block.lo[2]; z < block.hi[2]; ++z)
      for (int y = block.lo[1]; y < block.hi[1]; ++y)
        f(lattice.index(IVec<3>(block.lo[0], y, z)), length);
  }
}

}  // namespace mgelastic::grid
