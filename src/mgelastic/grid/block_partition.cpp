#include "mgelastic/grid/block_partition.hpp"

#include <algorithm>

namespace mgelastic::grid {

template <>
IVec<2> default_block_size<2>(const Lattice<2>&) {
  return IVec<2>(16, 16);
}

// Long x-rows: the sweeps stream each block row by row, and at 128^3 rows of 16 cells (one
// cache line per field) left the hardware prefetchers idle; 64 made the distributive and band
// sweeps about 1.8x and 1.4x cheaper at the same convergence rate
// (docs/notes/2026-12-07-performance-history.md), whole rows of 128 the distributive sweep
// another 12-22 % (128^3 box, armadillo at 256 cells) and of 256 another 22 % (256^3 box), at
// the same rates. Whole rows make a block's rows of one layer one stretch of memory, and 16 of
// them (128^3) cut the cycle another 9 %. So a block takes whole
// lattice rows (up to kMaxBlockRow, which keeps blocks for many threads), as many rows along y
// (4 to 16) as make a layer about kLayerCells, and 8 layers along z (fewer where that passes
// kBlockCells, whose fields stay in a core's L2 cache through the sweep's four passes). Thin
// blocks (128 x 8 x 4) made the block-local band order a weaker smoother (BandSweepOrder test).
template <>
IVec<3> default_block_size<3>(const Lattice<3>& lattice) {
  constexpr int kMaxBlockRow = 512, kLayerCells = 2048, kBlockCells = 16384;
  const int row = std::clamp(lattice.cells[0], 1, kMaxBlockRow);
  const int rows = std::clamp(kLayerCells / row, 4, 16);
  return IVec<3>(row, rows, std::clamp(kBlockCells / (row * rows), 2, 8));
}

template <int Dim>
int BlockPartition<Dim>::color_of(const IVec<Dim>& s) const {
  int color = 0;
  for (int a = 0; a < Dim; ++a) color |= (((s[a] - 1) / block_size[a]) & 1) << a;
  return color;
}

template <int Dim>
BlockPartition<Dim> partition_into_blocks(const Lattice<Dim>& lattice,
                                          const IVec<Dim>& block_size) {
  BlockPartition<Dim> partition;
  partition.block_size = block_size;
  for (int a = 0; a < Dim; ++a)
    partition.blocks_per_axis[a] = (lattice.cells[a] + block_size[a] - 1) / block_size[a];
  IVec<Dim> b = IVec<Dim>::Zero();
  const int total = partition.blocks_per_axis.prod();
  for (int index = 0; index < total; ++index) {
    int rest = index;
    for (int a = 0; a < Dim; ++a) {
      b[a] = rest % partition.blocks_per_axis[a];
      rest /= partition.blocks_per_axis[a];
    }
    Block<Dim> block;
    int color = 0;
    for (int a = 0; a < Dim; ++a) {
      block.lo[a] = 1 + b[a] * block_size[a];
      block.hi[a] = std::min(block.lo[a] + block_size[a], lattice.cells[a] + 1);
      color |= (b[a] & 1) << a;
    }
    partition.colors[color].push_back(block);
  }
  return partition;
}

template struct BlockPartition<2>;
template struct BlockPartition<3>;
template BlockPartition<2> partition_into_blocks<2>(const Lattice<2>&, const IVec<2>&);
template BlockPartition<3> partition_into_blocks<3>(const Lattice<3>&, const IVec<3>&);

}  // namespace mgelastic::grid
