#include "mgelastic/grid/band_block_shapes.hpp"

#include <algorithm>
#include <string>
#include <unordered_map>

#include "mgelastic/core/bytes.hpp"
#include "mgelastic/grid/band_kernel.hpp"
#include "mgelastic/grid/level.hpp"

namespace mgelastic::grid {

template <typename Scalar>
std::size_t BandBlockShapes<Scalar>::bytes() const {
  return vector_bytes(shape) + vector_bytes(column_start) + vector_bytes(column_field) +
         vector_bytes(column_offset) + vector_bytes(column_values) + vector_bytes(column_bytes) +
         vector_bytes(column_bytes_for);
}

template <typename Scalar>
void address_columns(BandBlockShapes<Scalar>& shapes, std::span<const Scalar* const> x) {
  address_by_field(x, shapes.column_field, shapes.column_offset, shapes.column_bytes,
                   shapes.column_bytes_for);
}

template <int Dim, typename Scalar>
void build_band_block_shapes(Level<Dim, Scalar>& level) {
  constexpr int L = BandBlockShapes<Scalar>::kLanes;
  static_assert(2 * Dim <= L);
  const BandKernel<Scalar>& kernel = level.band_kernel;
  BandBlockShapes<Scalar> shapes;
  std::unordered_map<std::string, std::uint32_t> ids;
  std::string key;
  shapes.shape.reserve(level.band_blocks.size());
  for (const auto& members : level.band_blocks) {
    const std::ptrdiff_t base = kernel.target[members[0]];
    key.clear();
    for (const std::uint32_t m : members) {
      if (m == UINT32_MAX) break;
      append_bytes(key, kernel.pattern[m]);
      append_bytes(key, kernel.field[m]);
      append_bytes(key, static_cast<std::int64_t>(kernel.target[m] - base));
    }
    const auto [it, added] = ids.try_emplace(key, static_cast<std::uint32_t>(ids.size()));
    shapes.shape.push_back(it->second);
    if (!added) continue;
    if (ids.size() > kShapesAlways && ids.size() * kMinBlocksPerShape > level.band_blocks.size()) {
      level.band_block_shapes = {};  // the blocks do not repeat: the pattern path
      return;
    }
    // The new shape's columns in first-read order, each member's coefficient in its lane.
    const std::size_t first = shapes.column_field.size();
    for (int a = 0; a < 2 * Dim && members[a] != UINT32_MAX; ++a) {
      const std::uint32_t m = members[a];
      const std::uint32_t p = kernel.pattern[m];
      const std::ptrdiff_t self = kernel.target[m] - base;
      for (std::uint32_t e = kernel.start[p]; e < kernel.start[p + 1]; ++e) {
        const auto offset = static_cast<std::int32_t>(self + kernel.entry_offset[e]);
        std::size_t c = first;
        while (c < shapes.column_field.size() && (shapes.column_field[c] != kernel.entry_field[e] ||
                                                  shapes.column_offset[c] != offset))
          ++c;
        if (c == shapes.column_field.size()) {
          shapes.column_field.push_back(kernel.entry_field[e]);
          shapes.column_offset.push_back(offset);
          shapes.column_values.resize(shapes.column_values.size() + L, Scalar(0));
        }
        shapes.column_values[c * L + a] += kernel.entry_value[e];
      }
    }
    shapes.column_start.push_back(static_cast<std::uint32_t>(shapes.column_field.size()));
  }
  shapes.shape.shrink_to_fit();
  level.band_block_shapes = std::move(shapes);
}

#define MGELASTIC_INSTANTIATE(D, S) template void build_band_block_shapes<D, S>(Level<D, S>&);
MGELASTIC_INSTANTIATE(2, float)
MGELASTIC_INSTANTIATE(2, double)
MGELASTIC_INSTANTIATE(3, float)
MGELASTIC_INSTANTIATE(3, double)
#undef MGELASTIC_INSTANTIATE
template struct BandBlockShapes<float>;
template struct BandBlockShapes<double>;
template void address_columns<float>(BandBlockShapes<float>&, std::span<const float* const>);
template void address_columns<double>(BandBlockShapes<double>&, std::span<const double* const>);

}  // namespace mgelastic::grid
