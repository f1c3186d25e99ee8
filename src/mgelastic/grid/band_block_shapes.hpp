#pragma once
// Dense form of the band's cell blocks for the step-by-step sweeps (boundary_smoother.cpp).
//
// A cell block's members (the band faces of one eliminated cell, up to 2d rows) read ~73 values
// through their patterns, but only ~31 distinct ones (armadillo at 256 cells): the faces of a
// cell read each other and their common neighbours. So per block shape (its members' patterns,
// fields and offsets from member 0's target) the distinct columns are stored once, each with
// the coefficients of all members side by side (member a in lane a of kLanes):
//   r_a = rhs_a - sum_c values[c][a] * x(column c),
// one load of x and one vector multiply-add per column instead of one scalar product per entry
// (the embedded band is bound by its instructions: docs/notes/2026-12-08-band-cost-floor.md).
// The sums are the residuals of the pattern rows up to round-off (another order, fused).
//
// Shapes repeat where the rows do: on a finest level without fill weights (3 401 shapes for
// 184 461 blocks on the armadillo at 256). A large level whose blocks seldom repeat (weighted
// coarse levels: 37 517 shapes for 45 257 blocks) keeps the pattern path.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace mgelastic::grid {

template <int Dim, typename Scalar>
struct Level;

template <typename Scalar>
struct BandBlockShapes {
  static constexpr int kLanes = 8;   // >= 2 Dim members; one AVX vector of floats
  std::vector<std::uint32_t> shape;  // per band block (Level::band_blocks)
  // Per shape: its columns [column_start[s], column_start[s + 1]).
  std::vector<std::uint32_t> column_start{0};
  // Per column: field, flat offset from member 0's target, kLanes coefficients.
  std::vector<std::uint8_t> column_field;
  std::vector<std::int32_t> column_offset;
  std::vector<Scalar> column_values;
  // Per column, its byte distance from member 0's point of field 0 for the field arrays at
  // column_bytes_for (address_columns), as BandKernel::entry_bytes.
  std::vector<std::intptr_t> column_bytes;
  std::vector<std::uintptr_t> column_bytes_for;

  bool built_for(std::size_t blocks) const { return !shape.empty() && shape.size() == blocks; }
  std::size_t shapes() const { return column_start.size() - 1; }
  std::size_t bytes() const;

  // The members' residuals before the right-hand side: sums[a] = sum_c values[c][a] x(c) for
  // block `block` whose member 0's target is `target` (x0: field 0 of the addressed arrays).
  void row_sums(const Scalar* x0, std::size_t target, std::size_t block, Scalar* sums) const {
    const std::uint32_t s = shape[block];
    const std::uintptr_t self = reinterpret_cast<std::uintptr_t>(x0 + target);
    alignas(32) Scalar acc[kLanes] = {};
    for (std::uint32_t c = column_start[s]; c < column_start[s + 1]; ++c) {
      const Scalar v = *reinterpret_cast<const Scalar*>(self + column_bytes[c]);
      const Scalar* w = column_values.data() + static_cast<std::size_t>(c) * kLanes;
#pragma omp simd
      for (int l = 0; l < kLanes; ++l) acc[l] += w[l] * v;
    }
    for (int l = 0; l < kLanes; ++l) sums[l] = acc[l];
  }
};

// The dense shapes of level.band_blocks (from band_kernel's patterns), or none where the level
// has more than kShapesAlways shapes and more than one per kMinBlocksPerShape blocks (a shape
// holds ~1.4 KB: small levels take the dense form whatever their repeats, large ones only where
// the blocks repeat).
inline constexpr std::size_t kShapesAlways = 4096;
inline constexpr std::size_t kMinBlocksPerShape = 8;
template <int Dim, typename Scalar>
void build_band_block_shapes(Level<Dim, Scalar>& level);

// Builds shapes.column_bytes for the field arrays x unless built for them already.
template <typename Scalar>
void address_columns(BandBlockShapes<Scalar>& shapes, std::span<const Scalar* const> x);

}  // namespace mgelastic::grid
