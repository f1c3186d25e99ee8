#include "mgelastic/grid/band_kernel.hpp"

#include <cstring>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <utility>

#include "mgelastic/core/bytes.hpp"
#include "mgelastic/grid/level.hpp"

namespace mgelastic::grid {
template <typename Scalar>
std::size_t BandKernel<Scalar>::bytes() const {
  return vector_bytes(pattern) + vector_bytes(target) + vector_bytes(field) +
         vector_bytes(constant) + vector_bytes(rhs) + vector_bytes(start) +
         vector_bytes(schur_diagonal) + vector_bytes(pressure_offset) +
         vector_bytes(pressure_factor) + vector_bytes(pressure_count) + vector_bytes(entry_field) +
         vector_bytes(entry_offset) + vector_bytes(entry_value) + vector_bytes(entry_bytes) +
         vector_bytes(entry_bytes_for);
}

template <typename Scalar>
void address_by_field(std::span<const Scalar* const> x, const std::vector<std::uint8_t>& field,
                      const std::vector<std::int32_t>& offset, std::vector<std::intptr_t>& bytes,
                      std::vector<std::uintptr_t>& bytes_for) {
  bool current = bytes.size() == offset.size() && bytes_for.size() == x.size();
  for (std::size_t f = 0; current && f < x.size(); ++f)
    current = bytes_for[f] == reinterpret_cast<std::uintptr_t>(x[f]);
  if (current) return;  // every band call asks: nothing allocated then
  bytes_for.resize(x.size());
  for (std::size_t f = 0; f < x.size(); ++f) bytes_for[f] = reinterpret_cast<std::uintptr_t>(x[f]);
  bytes.resize(offset.size());
  for (std::size_t e = 0; e < bytes.size(); ++e)
    bytes[e] = static_cast<std::intptr_t>(bytes_for[field[e]] - bytes_for[0]) +
               static_cast<std::intptr_t>(offset[e]) * static_cast<std::intptr_t>(sizeof(Scalar));
}

template <typename Scalar>
void address_entries(BandKernel<Scalar>& kernel, std::span<const Scalar* const> x) {
  address_by_field(x, kernel.entry_field, kernel.entry_offset, kernel.entry_bytes,
                   kernel.entry_bytes_for);
}

namespace {

// Row m's entries as (field, offset from the row's own index, value): appended to a pattern's
// key, and to the kernel's entries when the pattern is new.
template <typename Scalar>
void append_entry_key(std::string& key, const SparseRows<Scalar>& rows, std::size_t m) {
  const auto self = static_cast<std::int64_t>(rows.target_index[m]);
  for (std::uint32_t e = rows.start[m]; e < rows.start[m + 1]; ++e) {
    append_bytes(key, rows.column_field[e]);
    append_bytes(key, static_cast<std::int32_t>(rows.column_index[e] - self));
    append_bytes(key, rows.value[e]);
  }
}
template <typename Scalar>
void append_entries(BandKernel<Scalar>& kernel, const SparseRows<Scalar>& rows, std::size_t m) {
  const auto self = static_cast<std::int64_t>(rows.target_index[m]);
  for (std::uint32_t e = rows.start[m]; e < rows.start[m + 1]; ++e) {
    kernel.entry_field.push_back(rows.column_field[e]);
    kernel.entry_offset.push_back(static_cast<std::int32_t>(rows.column_index[e] - self));
    kernel.entry_value.push_back(rows.value[e]);
  }
  kernel.start.push_back(static_cast<std::uint32_t>(kernel.entry_value.size()));
}

// An empty kernel for `rows`: their targets, room for their pattern ids.
template <typename Scalar>
BandKernel<Scalar> kernel_for(const SparseRows<Scalar>& rows) {
  BandKernel<Scalar> kernel;
  kernel.pattern.reserve(rows.rows());
  kernel.target = rows.target_index;
  return kernel;
}

}  // namespace

template <int Dim, typename Scalar>
void build_band_kernel(Level<Dim, Scalar>& level) {
  const SparseRows<Scalar>& rows = level.band_u;
  BandKernel<Scalar> kernel = kernel_for(rows);
  kernel.field = rows.target_field;
  kernel.constant = rows.constant;
  kernel.rhs.assign(rows.rows(), Scalar(0));
  // Patterns are identified by their exact bytes, so a shared pattern is bit-identical to
  // every row that uses it.
  std::unordered_map<std::string, std::uint32_t> ids;
  std::string key;
  for (std::size_t m = 0; m < rows.rows(); ++m) {
    const auto self = static_cast<std::int64_t>(rows.target_index[m]);
    key.clear();
    append_entry_key(key, rows, m);
    std::array<std::int32_t, 2> offset{0, 0};
    std::array<Scalar, 2> factor{0, 0};
    std::uint8_t count = 0;
    for (int c = 0; c < 2; ++c) {
      const std::uint32_t cell = level.band_u_pressure[m][c];
      if (cell == UINT32_MAX) continue;
      offset[count] = static_cast<std::int32_t>(cell - self);
      factor[count++] = level.band_u_pressure_factor[m][c];
    }
    append_bytes(key, level.band_u_schur_diagonal[m]);
    append_bytes(key, count);
    for (int c = 0; c < count; ++c) {
      append_bytes(key, offset[c]);
      append_bytes(key, factor[c]);
    }
    const auto [it, added] = ids.try_emplace(key, static_cast<std::uint32_t>(kernel.patterns()));
    kernel.pattern.push_back(it->second);
    if (!added) continue;
    append_entries(kernel, rows, m);
    kernel.schur_diagonal.push_back(level.band_u_schur_diagonal[m]);
    kernel.pressure_offset.push_back(offset);
    kernel.pressure_factor.push_back(factor);
    kernel.pressure_count.push_back(count);
  }
  level.band_kernel = std::move(kernel);
  build_band_pressure_kernel(level);
  if (level.x[0].size() != level.size()) return;  // no arrays yet: the first sweep addresses
  std::array<const Scalar*, Dim + 1> x;
  for (int f = 0; f <= Dim; ++f) x[f] = level.x[f].data();
  address_entries<Scalar>(level.band_kernel, x);
  address_entries<Scalar>(level.band_p_kernel, x);
}

template <int Dim, typename Scalar>
void build_band_pressure_kernel(Level<Dim, Scalar>& level) {
  const SparseRows<Scalar>& rows = level.band_p;
  BandKernel<Scalar> kernel = kernel_for(rows);
  std::unordered_map<std::string, std::uint32_t> ids;
  std::string key;
  for (std::size_t m = 0; m < rows.rows(); ++m) {
    key.clear();
    append_entry_key(key, rows, m);
    const auto [it, added] =
        ids.try_emplace(key, static_cast<std::uint32_t>(kernel.start.size() - 1));
    kernel.pattern.push_back(it->second);
    if (!added) continue;
    append_entries(kernel, rows, m);
  }
  level.band_p_kernel = std::move(kernel);
}

template <int Dim, typename Scalar>
void drop_band_csr(Level<Dim, Scalar>& level) {
  // Assigning a fresh object frees the storage (`v = {}` would keep a vector's capacity).
  const auto release = [](auto&... v) { ((v = std::remove_cvref_t<decltype(v)>()), ...); };
  release(level.band_u, level.band_u_schur_diagonal, level.band_u_pressure,
          level.band_u_pressure_factor);
}

template struct BandKernel<float>;
template struct BandKernel<double>;
template void address_entries<float>(BandKernel<float>&, std::span<const float* const>);
template void address_by_field<float>(std::span<const float* const>,
                                      const std::vector<std::uint8_t>&,
                                      const std::vector<std::int32_t>&, std::vector<std::intptr_t>&,
                                      std::vector<std::uintptr_t>&);
template void address_by_field<double>(std::span<const double* const>,
                                       const std::vector<std::uint8_t>&,
                                       const std::vector<std::int32_t>&,
                                       std::vector<std::intptr_t>&, std::vector<std::uintptr_t>&);
template void address_entries<double>(BandKernel<double>&, std::span<const double* const>);
template void build_band_kernel<2, float>(Level<2, float>&);
template void build_band_pressure_kernel<2, float>(Level<2, float>&);
template void build_band_kernel<2, double>(Level<2, double>&);
template void build_band_pressure_kernel<2, double>(Level<2, double>&);
template void build_band_kernel<3, float>(Level<3, float>&);
template void build_band_pressure_kernel<3, float>(Level<3, float>&);
template void build_band_kernel<3, double>(Level<3, double>&);
template void build_band_pressure_kernel<3, double>(Level<3, double>&);
template void drop_band_csr<2, float>(Level<2, float>&);
template void drop_band_csr<2, double>(Level<2, double>&);
template void drop_band_csr<3, float>(Level<3, float>&);
template void drop_band_csr<3, double>(Level<3, double>&);

}  // namespace mgelastic::grid
