#include "mgelastic/grid/layout_census.hpp"

#include <algorithm>

namespace mgelastic::grid {
namespace {

inline constexpr std::ptrdiff_t kFloatPage = 1024;  // floats in a 4 KiB page

// 1 where some field has a variable.
template <int Dim, typename Scalar>
std::vector<std::uint8_t> variable_mask(const Level<Dim, Scalar>& level) {
  std::vector<std::uint8_t> mask(level.size(), 0);
  for (int f = 0; f <= Dim; ++f)
    for (std::size_t k = 0; k < level.size(); ++k)
      mask[k] |= level.kind(f, k) != VarKind::INACTIVE ? 1 : 0;
  return mask;
}

// visit(k, s) for every storage point k with stored coordinates s, in flat order (the
// coordinates kept like an odometer: no divisions).
template <int Dim, typename Visit>
void for_each_point(const Lattice<Dim>& lattice, Visit&& visit) {
  IVec<Dim> s = IVec<Dim>::Zero();
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(lattice.size()); ++k) {
    visit(k, s);
    for (int a = 0; a < Dim && ++s[a] == lattice.padded(a); ++a) s[a] = 0;
  }
}

// The mask grown by one point along each axis in turn: the 3^Dim points around each set point.
template <int Dim>
std::vector<std::uint8_t> dilated(const Lattice<Dim>& lattice, std::vector<std::uint8_t> mask) {
  for (int a = 0; a < Dim; ++a) {
    const std::ptrdiff_t stride = lattice.stride(a);
    std::vector<std::uint8_t> grown = mask;
    for_each_point(lattice, [&](std::ptrdiff_t k, const IVec<Dim>& s) {
      if (!mask[k]) return;
      if (s[a] > 0) grown[k - stride] = 1;
      if (s[a] + 1 < lattice.padded(a)) grown[k + stride] = 1;
    });
    mask = std::move(grown);
  }
  return mask;
}

template <int Dim>
TileCensus count_tiles(const Lattice<Dim>& lattice, const std::vector<std::uint8_t>& needed,
                       const std::array<int, 3>& size) {
  std::array<int, Dim> per_axis{};
  std::size_t tile_count = 1, tile_points = 1;
  for (int a = 0; a < Dim; ++a) {
    per_axis[a] = (lattice.padded(a) + size[a] - 1) / size[a];
    tile_count *= static_cast<std::size_t>(per_axis[a]);
    tile_points *= static_cast<std::size_t>(size[a]);
  }
  std::vector<std::uint8_t> used(tile_count, 0);
  for_each_point(lattice, [&](std::ptrdiff_t k, const IVec<Dim>& s) {
    if (!needed[k]) return;
    std::size_t tile = 0, stride = 1;
    for (int a = 0; a < Dim; ++a) {
      tile += static_cast<std::size_t>(s[a] / size[a]) * stride;
      stride *= static_cast<std::size_t>(per_axis[a]);
    }
    used[tile] = 1;
  });
  TileCensus census;
  census.size = size;
  census.tiles = static_cast<std::size_t>(std::count(used.begin(), used.end(), 1));
  census.points = census.tiles * tile_points;
  return census;
}

std::size_t live_page_points(const std::vector<std::uint8_t>& mask) {
  std::size_t points = 0;
  for (std::size_t begin = 0; begin < mask.size(); begin += kFloatPage) {
    const std::size_t end = std::min(mask.size(), begin + kFloatPage);
    if (std::any_of(mask.begin() + static_cast<std::ptrdiff_t>(begin),
                    mask.begin() + static_cast<std::ptrdiff_t>(end),
                    [](std::uint8_t v) { return v != 0; }))
      points += kFloatPage;
  }
  return points;
}

// Points of one x-range per storage row: from the first to the last needed point of the row.
template <int Dim>
std::size_t row_range_points(const Lattice<Dim>& lattice, const std::vector<std::uint8_t>& needed) {
  const std::ptrdiff_t n = lattice.padded(0);
  std::size_t points = 0;
  for (std::size_t begin = 0; begin < needed.size(); begin += static_cast<std::size_t>(n)) {
    const auto first = needed.begin() + static_cast<std::ptrdiff_t>(begin);
    const auto last = first + n;
    const auto lo = std::find(first, last, 1);
    if (lo == last) continue;
    const auto hi = std::find(std::make_reverse_iterator(last), std::make_reverse_iterator(lo), 1);
    points += static_cast<std::size_t>(hi.base() - lo);
  }
  return points;
}

}  // namespace

template <int Dim, typename Scalar>
LayoutCensus layout_census(const Level<Dim, Scalar>& level,
                           const std::vector<std::array<int, 3>>& tile_sizes) {
  const std::vector<std::uint8_t> mask = variable_mask(level);
  const std::vector<std::uint8_t> needed = dilated(level.lattice, mask);
  LayoutCensus census;
  census.active_cells = static_cast<std::size_t>(
      std::count(level.cells.begin(), level.cells.end(), CellType::INTERIOR));
  census.bounding_box = level.size();
  census.with_variables = static_cast<std::size_t>(std::count(mask.begin(), mask.end(), 1));
  census.live_pages = live_page_points(mask);
  census.row_ranges = row_range_points(level.lattice, needed);
  for (const auto& size : tile_sizes)
    census.tiles.push_back(count_tiles(level.lattice, needed, size));
  return census;
}

template <int Dim, typename Scalar>
LayoutCensus layout_census(const std::vector<const Level<Dim, Scalar>*>& levels,
                           const std::vector<std::array<int, 3>>& tile_sizes) {
  LayoutCensus total;
  for (std::size_t l = 0; l < levels.size(); ++l) {
    const LayoutCensus one = layout_census(*levels[l], tile_sizes);
    if (l == 0) {
      total = one;
      continue;
    }
    total.bounding_box += one.bounding_box;
    total.with_variables += one.with_variables;
    total.live_pages += one.live_pages;
    total.row_ranges += one.row_ranges;
    for (std::size_t t = 0; t < one.tiles.size(); ++t) {
      total.tiles[t].tiles += one.tiles[t].tiles;
      total.tiles[t].points += one.tiles[t].points;
    }
  }
  return total;
}

#define MGELASTIC_INSTANTIATE(D, S)                                                  \
  template LayoutCensus layout_census<D, S>(const Level<D, S>&,                      \
                                            const std::vector<std::array<int, 3>>&); \
  template LayoutCensus layout_census<D, S>(const std::vector<const Level<D, S>*>&,  \
                                            const std::vector<std::array<int, 3>>&);
MGELASTIC_INSTANTIATE(2, float)
MGELASTIC_INSTANTIATE(2, double)
MGELASTIC_INSTANTIATE(3, float)
MGELASTIC_INSTANTIATE(3, double)
#undef MGELASTIC_INSTANTIATE

}  // namespace mgelastic::grid
