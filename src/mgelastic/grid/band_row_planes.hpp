#pragma once
// The boundary band's explicit rows grouped by the lattice plane of their target (planes normal
// to the last axis, flat index / stride(Dim - 1)), so a pass over a window of planes
// (residual_restriction.hpp) finds its band rows without searching. Per plane, rows keep their
// order; each row writes only its own target, so the grouping changes no value.
//
// Lines: where the level's band runs are built (band_runs.hpp), the momentum rows of one member
// of one run (its steps one cell apart along x, or one row apart along y, in one plane) are
// evaluated together, the loads of each pattern entry contiguous along the run (vectorized:
// the 128^3 box has 99 % of its band rows in runs). momentum_rows then holds only the rows
// outside the lines (cell blocks share faces, so runs may share rows: each row is in one line
// at most). Each line row's residual is summed in BandKernel::row_sum's entry order.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mgelastic/grid/level.hpp"

namespace mgelastic::grid {

struct BandRowPlanes {
  // CSR over planes: the rows of plane z are rows[start[z] .. start[z + 1]).
  std::vector<std::uint32_t> momentum_start, momentum_rows;  // BandKernel (band_u) rows
  std::vector<std::uint32_t> pressure_start, pressure_rows;  // band_p rows
  // Run members by plane: line_start like momentum_start; each line is run index * kLineMembers
  // + member (Level::band_runs); empty without runs.
  static constexpr std::uint32_t kLineMembers = 8;
  std::vector<std::uint32_t> line_start, lines;
  std::size_t rows_in_lines = 0;

  template <int Dim, typename Scalar>
  bool valid_for(const Level<Dim, Scalar>& level) const {
    const auto planes = static_cast<std::size_t>(level.lattice.padded(Dim - 1));
    return momentum_start.size() == planes + 1 && pressure_start.size() == planes + 1 &&
           momentum_rows.size() + rows_in_lines == level.band_kernel.rows() &&
           pressure_rows.size() == level.band_p.rows() &&
           (rows_in_lines == 0 || (line_start.size() == planes + 1 &&
                                   level.band_runs.valid_for(level.band_kernel.rows())));
  }
  std::size_t bytes() const {
    return sizeof(std::uint32_t) *
           (momentum_start.capacity() + momentum_rows.capacity() + pressure_start.capacity() +
            pressure_rows.capacity() + line_start.capacity() + lines.capacity());
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
  // Run members whose steps share a plane become lines; their rows leave momentum_rows.
  std::vector<std::uint8_t> in_line(kernel.rows(), 0);
  std::vector<std::uint32_t> lines;
  const BandRuns<Dim, Scalar>& runs = level.band_runs;
  if (runs.valid_for(kernel.rows())) {
    for (std::size_t i = 0; i < runs.runs.size(); ++i) {
      const BandRun& run = runs.runs[i];
      const BandRunShape<Dim, Scalar>& shape = runs.shapes[run.shape];
      for (int a = 0; a < shape.members; ++a) {
        const std::ptrdiff_t first = run.target + shape.offset[a];
        const std::ptrdiff_t last = first + (run.length - 1) * run.stride;
        if (first / static_cast<std::ptrdiff_t>(stride) !=
            last / static_cast<std::ptrdiff_t>(stride))
          continue;
        // Cell blocks share faces, so a row may be a member of several runs: one line has it.
        const auto row = [&](std::uint32_t s) {
          return runs.rows[run.first_row + s * shape.members + a];
        };
        bool taken = false;
        for (std::uint32_t s = 0; s < run.length; ++s) taken = taken || in_line[row(s)];
        if (taken) continue;
        lines.push_back(static_cast<std::uint32_t>(i) * BandRowPlanes::kLineMembers + a);
        for (std::uint32_t s = 0; s < run.length; ++s) in_line[row(s)] = 1;
        grouped.rows_in_lines += run.length;
      }
    }
  }
  const auto line_plane = [&](std::size_t i) {
    const BandRun& run = runs.runs[lines[i] / BandRowPlanes::kLineMembers];
    const int a = static_cast<int>(lines[i] % BandRowPlanes::kLineMembers);
    return static_cast<std::size_t>(run.target + runs.shapes[run.shape].offset[a]) / stride;
  };
  std::vector<std::uint32_t> order;
  detail::group_by_plane(lines.size(), planes, line_plane, grouped.line_start, order);
  grouped.lines.resize(lines.size());
  for (std::size_t i = 0; i < order.size(); ++i) grouped.lines[i] = lines[order[i]];
  std::vector<std::uint32_t> outside;
  for (std::size_t m = 0; m < kernel.rows(); ++m)
    if (!in_line[m]) outside.push_back(static_cast<std::uint32_t>(m));
  detail::group_by_plane(
      outside.size(), planes, [&](std::size_t i) { return kernel.target[outside[i]] / stride; },
      grouped.momentum_start, order);
  grouped.momentum_rows.resize(order.size());
  for (std::size_t i = 0; i < order.size(); ++i) grouped.momentum_rows[i] = outside[order[i]];
  detail::group_by_plane(
      level.band_p.rows(), planes,
      [&](std::size_t m) { return level.band_p.target_index[m] / stride; }, grouped.pressure_start,
      grouped.pressure_rows);
  return grouped;
}

}  // namespace mgelastic::grid
