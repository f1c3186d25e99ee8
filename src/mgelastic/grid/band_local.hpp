#pragma once
// The boundary band's Gauss-Seidel sweeps (Sec. 5.3) on a compact band-local vector.
//
// A band row reads up to ~20 lattice values in four fields and three planes. On the faces
// normal to x those values lie one per cache line (the lattice is x-fastest), so a sweep over
// the lattice arrays moves ~16x the bytes it uses and waits on misses (perf: ~70 % of the
// sweep on the x loads). A band_gauss_seidel call therefore gathers every variable its rows
// read or write into a contiguous vector xl (the lattice with every other value left out:
// field by field in lattice order, so a row's neighbours stay a few entries apart), runs all
// of its sweeps there, and scatters back:
//   xl[i] = x[field_i][index_i]   (gather, in lattice order)
//   sweeps: the band_schedule's order, cell blocks (delta = S_loc^-1 r) and point rows,
//           r = rhs - sum_e value_e xl[column_e]   (values from the BandKernel patterns)
//   x[field_i][index_i] = xl[i]   (scatter)
// The arithmetic is the step-by-step sweep's, entry for entry, so results equal it bit for bit.
//
// Layout: per band_u row (the kernel's order; pattern, rhs, cell blocks and the colored
// schedule are the level's own) the local index of its variable, its first column and its
// eliminated pressures' local indices; per row entry a local column (pattern entry order); per
// variable its lattice index. Derived from band_kernel: rebuild with build_band_local after it
// changes (stale ones are not used: valid_for).
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace mgelastic::grid {

template <int Dim, typename Scalar>
struct Level;

template <int Dim, typename Scalar>
struct BandLocal {
  // Per band_u row.
  std::vector<std::uint32_t> self;                     // local index of the row's variable
  std::vector<std::uint32_t> first_column;             // into column; rows + 1 entries
  std::vector<std::array<std::uint32_t, 2>> pressure;  // local indices (count from the pattern)
  std::vector<std::uint32_t> column;                   // per row entry: local index
  // Per local variable (lattice order: field by field, ascending index) its lattice index;
  // field f's variables are [start[f], start[f + 1]). Gathered before and scattered after the
  // sweeps.
  struct Gather {
    std::array<std::uint32_t, Dim + 2> start{};
    std::vector<std::uint32_t> index;
  };
  Gather gather;
  std::vector<Scalar> x;  // the compact vector, sized at build
  std::size_t band_rows = 0;

  bool valid_for(std::size_t band_u_rows) const { return band_rows == band_u_rows && band_rows; }
  std::size_t bytes() const;
};

// Builds Level::band_local (needs band_kernel).
template <int Dim, typename Scalar>
void build_band_local(Level<Dim, Scalar>& level);

// `sweeps` sweeps of Level::band_schedule (or, when `rows` is given, point sweeps over that row
// schedule, e.g. the Fig. 8 rows) on the compact vector: gather, sweeps, scatter. kernel.rhs
// must hold b - constant for the rows swept (band_gauss_seidel refreshes it).
template <int Dim, typename Scalar>
void band_local_sweeps(Level<Dim, Scalar>& level, int sweeps,
                       const typename Level<Dim, Scalar>::RowSchedule* rows = nullptr);

}  // namespace mgelastic::grid
