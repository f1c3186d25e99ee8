#pragma once
// Compact form of the boundary band's momentum rows for the Gauss-Seidel sweeps (Sec. 5.3).
//
// Most band rows of a level repeat one of few shapes (a flat face, an edge, a corner, ...): the
// same coefficients at the same offsets from the row's own variable. The sweeps stream every
// band row a dozen times per V-cycle, so each row keeps only its target and a pattern id; the
// distinct patterns (columns as (field, offset from the target's flat index), values, Schur
// diagonal, eliminated-pressure factors) are stored once and stay in cache. Entry order and
// values equal those of Level::band_u, so sums round exactly as with the CSR rows.
//
// Derived data: build_band_kernel() must run again after band_u, band_u_schur_diagonal or the
// pressure factors change (build_level calls it). Once built, the kernel is the band's only
// form a solve needs (sweeps, residuals, Fig. 8 rows): drop_band_csr() frees band_u's CSR rows,
// which hold ~20 (field, index, value) entries per row, 6-7x the kernel's bytes (Multigrid does,
// on every level; levels built directly by build_level keep both forms).
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace mgelastic::grid {

template <int Dim, typename Scalar>
struct Level;

template <typename Scalar>
struct BandKernel {
  // Per band_u row.
  std::vector<std::uint32_t> pattern;  // pattern id
  std::vector<std::uint32_t> target;   // flat index of the row's own variable
  std::vector<std::uint8_t> field;     // its field
  std::vector<Scalar> constant;        // boundary stresses moved to the right-hand side
  std::vector<Scalar> rhs;             // b - constant, refreshed by each band_gauss_seidel call
  // Per pattern: entries [start, start + 1), Schur diagonal, up to two eliminated pressures
  // at cell offsets from the target (factor 0 and offset 0 when absent).
  std::vector<std::uint32_t> start{0};
  std::vector<Scalar> schur_diagonal;
  std::vector<std::array<std::int32_t, 2>> pressure_offset;
  std::vector<std::array<Scalar, 2>> pressure_factor;
  std::vector<std::uint8_t> pressure_count;
  // Per pattern entry.
  std::vector<std::uint8_t> entry_field;
  std::vector<std::int32_t> entry_offset;
  std::vector<Scalar> entry_value;
  // Per pattern entry, the byte distance of its value from the row's own point of field 0,
  // (x[field] - x[0]) + offset * sizeof(Scalar), for the field arrays at entry_bytes_for
  // (address_entries). The sweeps read a row's values through that one base address: they are
  // bound by the instructions per entry, and a field pointer per entry costs two more.
  std::vector<std::intptr_t> entry_bytes;
  std::vector<std::uintptr_t> entry_bytes_for;

  std::size_t rows() const { return pattern.size(); }
  std::size_t patterns() const { return schur_diagonal.size(); }
  std::size_t bytes() const;

  // Row m's global variable index (Level::global) on a lattice of `size` points.
  std::uint32_t global_target(std::size_t m, std::size_t size) const {
    return static_cast<std::uint32_t>(field[m] * size + target[m]);
  }
  // Row value sum_e value_e x[field_e][target + offset_e] (the entries' order: the CSR sum;
  // each product rounded before it is added, as the band residual's vectorized lines do,
  // band_row_planes.hpp: a fused multiply-add would lengthen the sweeps' dependency chain).
  template <typename X>
  Scalar row_sum(const X& x, std::size_t m) const {
    const std::uint32_t p = pattern[m];
    const std::ptrdiff_t self = target[m];
    Scalar sum = 0;
    for (std::uint32_t e = start[p]; e < start[p + 1]; ++e)
      sum += entry_value[e] * x[entry_field[e]][self + entry_offset[e]];
    return sum;
  }
  // Whether entry_bytes is built for the arrays of x (address_entries).
  template <typename X>
  bool addressed_for(const X& x) const {
    if (entry_bytes.size() != entry_offset.size() || entry_bytes_for.size() != x.size())
      return false;
    for (std::size_t f = 0; f < x.size(); ++f)
      if (entry_bytes_for[f] != reinterpret_cast<std::uintptr_t>(&x[f][0])) return false;
    return true;
  }
  // row_sum through entry_bytes (x0: field 0 of the arrays it is built for): the same products
  // in the same order. Not vectorized: GCC's emulated gathers for these short loops cost more.
  [[gnu::optimize("no-tree-vectorize")]] Scalar addressed_row_sum(const Scalar* x0,
                                                                  std::size_t m) const {
    const std::uint32_t p = pattern[m];
    const std::uintptr_t self = reinterpret_cast<std::uintptr_t>(x0 + target[m]);
    const std::intptr_t* bytes = entry_bytes.data();
    const Scalar* value = entry_value.data();
    Scalar sum = 0;
    for (std::uint32_t e = start[p]; e < start[p + 1]; ++e)
      sum += value[e] * *reinterpret_cast<const Scalar*>(self + bytes[e]);
    return sum;
  }
};

template <int Dim, typename Scalar>
void build_band_kernel(Level<Dim, Scalar>& level);

// level.band_p_kernel from level.band_p: per row its pattern and target (the cell's pressure);
// per pattern its entries (field, offset, value), entry order and values those of band_p, so
// sums round as with its CSR rows. The other per-row and per-pattern arrays stay empty (band_p
// keeps the constants, Level::band_p_inverse the inverses). Called by build_band_kernel and,
// where band_p's rows changed, by the band sweeps' refresh (boundary_smoother.cpp).
template <int Dim, typename Scalar>
void build_band_pressure_kernel(Level<Dim, Scalar>& level);

// bytes[e] = (x[field[e]] - x[0]) + offset[e] * sizeof(Scalar), the byte distance of a value
// from the point of field 0, rebuilt only where x is not the arrays at bytes_for (a copied level
// has new arrays; a moved one keeps them).
template <typename Scalar>
void address_by_field(std::span<const Scalar* const> x, const std::vector<std::uint8_t>& field,
                      const std::vector<std::int32_t>& offset, std::vector<std::intptr_t>& bytes,
                      std::vector<std::uintptr_t>& bytes_for);

// Builds kernel.entry_bytes for the field arrays x unless it is built for these
// addresses already.
template <typename Scalar>
void address_entries(BandKernel<Scalar>& kernel, std::span<const Scalar* const> x);

// Frees band_u's CSR rows, Schur diagonals and pressure factors (all held by the kernel). Only
// after everything built from them (blocks, schedules, runs) exists.
template <int Dim, typename Scalar>
void drop_band_csr(Level<Dim, Scalar>& level);

}  // namespace mgelastic::grid
