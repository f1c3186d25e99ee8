#pragma once
// The boundary band's explicit rows grouped by the lattice plane of their target (planes normal
// to the last axis, flat index / stride(Dim - 1)), so a pass over a window of planes
// (residual_restriction.hpp) finds its band rows without searching. Per plane, rows keep their
// order; each row writes only its own target, so the grouping changes no value.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mgelastic/grid/level.hpp"

namespace mgelastic::grid {

struct BandRowPlanes {
  // CSR over planes: the rows of plane z are rows[start[z] .. start[z + 1]).
  std::vector<std::uint32_t> momentum_start, momentum_rows;  // BandKernel (band_u) rows
  std::vector<std::uint32_t> pressure_start, pressure_rows;  // band_p rows

  template <int Dim, typename Scalar>
  bool valid_for(const Level<Dim, Scalar>& level) const {
    const auto planes = static_cast<std::size_t>(level.lattice.padded(Dim - 1));
    return momentum_start.size() == planes + 1 && pressure_start.size() == planes + 1 &&
           momentum_rows.size() == level.band_kernel.rows() &&
           pressure_rows.size() == level.band_p.rows();
  }
  std::size_t bytes() const {
    return sizeof(std::uint32_t) * (momentum_start.capacity() + momentum_rows.capacity() +
                                    pressure_start.capacity() + pressure_rows.capacity());
  }
};

namespace detail {
// Counting sort of `count` rows by plane_of(row).
template <typename PlaneOf>
void group_by_plane(std::size_t count, std::size_t planes, const PlaneOf& plane_of,
                    std::vector<std::uint32_t>& start, std::vector<std::uint32_t>& rows) {
  start.assign(planes + 1, 0);
  for (std::size_t m = 0; m < count; ++m) ++start[plane_of(m) + 1];
  for (std::size_t z = 0; z < planes; ++z) start[z + 1] += start[z];
  std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
  rows.resize(count);
  for (std::size_t m = 0; m < count; ++m) rows[next[plane_of(m)]++] = static_cast<std::uint32_t>(m);
}
}  // namespace detail

template <int Dim, typename Scalar>
BandRowPlanes band_row_planes(const Level<Dim, Scalar>& level) {
  const auto planes = static_cast<std::size_t>(level.lattice.padded(Dim - 1));
  const auto stride = static_cast<std::size_t>(level.lattice.stride(Dim - 1));
  BandRowPlanes grouped;
  const BandKernel<Scalar>& kernel = level.band_kernel;
  detail::group_by_plane(
      kernel.rows(), planes, [&](std::size_t m) { return kernel.target[m] / stride; },
      grouped.momentum_start, grouped.momentum_rows);
  detail::group_by_plane(
      level.band_p.rows(), planes,
      [&](std::size_t m) { return level.band_p.target_index[m] / stride; }, grouped.pressure_start,
      grouped.pressure_rows);
  return grouped;
}

}  // namespace mgelastic::grid
