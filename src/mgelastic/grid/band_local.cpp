#include "mgelastic/grid/band_local.hpp"

#include <algorithm>
#include <numeric>

#include "mgelastic/core/bytes.hpp"
#include "mgelastic/grid/level.hpp"

namespace mgelastic::grid {
namespace {

inline constexpr std::uint32_t kUnassigned = UINT32_MAX;

// Numbers the variables the band rows read or write in lattice order (field by field,
// ascending index): the compact vector is then the lattice with the unused values left out, so
// a row's neighbours stay close (a face normal to x reads its y neighbours a few entries away,
// not a lattice row away), and gather and scatter stream both arrays in order.
template <int Dim, typename Scalar>
void number_variables(const Level<Dim, Scalar>& level, BandLocal<Dim, Scalar>& local) {
  const BandKernel<Scalar>& kernel = level.band_kernel;
  std::vector<std::uint32_t> id(static_cast<std::size_t>(Dim + 1) * level.size(), kUnassigned);
  // Visits row m's variables: its own, its entries' (pattern order), its eliminated pressures.
  const auto for_each_variable = [&](std::uint32_t m, auto&& visit) {
    const std::uint32_t p = kernel.pattern[m];
    const std::ptrdiff_t target = kernel.target[m];
    visit(level.global(kernel.field[m], target));
    for (std::uint32_t e = kernel.start[p]; e < kernel.start[p + 1]; ++e)
      visit(level.global(kernel.entry_field[e], target + kernel.entry_offset[e]));
    for (int c = 0; c < kernel.pressure_count[p]; ++c)
      visit(level.global(Dim, target + kernel.pressure_offset[p][c]));
  };
  const auto rows = static_cast<std::uint32_t>(kernel.rows());
  for (std::uint32_t m = 0; m < rows; ++m)
    for_each_variable(m, [&](std::uint32_t global) { id[global] = 0; });
  auto& gather = local.gather;
  const auto size = static_cast<std::uint32_t>(level.size());
  gather.start.fill(0);
  std::uint32_t next = 0;
  for (std::size_t global = 0; global < id.size(); ++global) {
    if (id[global] == kUnassigned) continue;
    id[global] = next++;
    gather.index.push_back(static_cast<std::uint32_t>(global % size));
    ++gather.start[global / size + 1];
  }
  std::partial_sum(gather.start.begin(), gather.start.end(), gather.start.begin());
  local.first_column.assign(1, 0);
  for (std::uint32_t m = 0; m < rows; ++m) {
    const std::uint32_t p = kernel.pattern[m];
    int seen = 0;
    std::array<std::uint32_t, 2> pressure{kUnassigned, kUnassigned};
    const auto entries = kernel.start[p + 1] - kernel.start[p];
    for_each_variable(m, [&](std::uint32_t global) {
      if (seen == 0)
        local.self.push_back(id[global]);
      else if (seen <= static_cast<int>(entries))
        local.column.push_back(id[global]);
      else
        pressure[seen - 1 - entries] = id[global];
      ++seen;
    });
    local.first_column.push_back(static_cast<std::uint32_t>(local.column.size()));
    local.pressure.push_back(pressure);
  }
  local.x.assign(next, Scalar(0));
}

// The sweep's operations on the compact vector (boundary_smoother.cpp's BandSweep, with local
// indices): same sums in the same order.
template <int Dim, typename Scalar>
struct LocalSweep {
  Scalar* x;
  const BandKernel<Scalar>& kernel;
  const BandLocal<Dim, Scalar>& local;
  const std::array<std::uint32_t, 2 * Dim>* blocks;
  const Scalar* block_inverse;
  const std::uint32_t* inverse_id;

  Scalar residual(std::uint32_t r) const {
    const std::uint32_t p = kernel.pattern[r];
    const std::uint32_t* column = local.column.data() + local.first_column[r];
    const Scalar* value = kernel.entry_value.data() + kernel.start[p];
    const std::uint32_t count = kernel.start[p + 1] - kernel.start[p];
    Scalar sum = 0;
    for (std::uint32_t e = 0; e < count; ++e) sum += value[e] * x[column[e]];
    return kernel.rhs[r] - sum;
  }

  void move(std::uint32_t r, Scalar delta) const {
    const std::uint32_t p = kernel.pattern[r];
    x[local.self[r]] += delta;
    for (int c = 0; c < kernel.pressure_count[p]; ++c)
      x[local.pressure[r][c]] -= kernel.pressure_factor[p][c] * delta;
  }

  void relax_row(std::uint32_t r) const {
    move(r, residual(r) / kernel.schur_diagonal[kernel.pattern[r]]);
  }

  void relax_block(std::uint32_t block) const {
    constexpr int B = 2 * Dim;
    const auto& members = blocks[block];
    std::array<Scalar, B> res{};
    for (int a = 0; a < B && members[a] != kUnassigned; ++a) res[a] = residual(members[a]);
    const Scalar* inverse = block_inverse + static_cast<std::size_t>(inverse_id[block]) * B * B;
    for (int a = 0; a < B && members[a] != kUnassigned; ++a) {
      Scalar delta = 0;
      for (int b = 0; b < B; ++b) delta += inverse[a * B + b] * res[b];
      move(members[a], delta);
    }
  }
};

}  // namespace

template <int Dim, typename Scalar>
std::size_t BandLocal<Dim, Scalar>::bytes() const {
  return vector_bytes(self) + vector_bytes(first_column) + vector_bytes(pressure) +
         vector_bytes(column) + vector_bytes(gather.index) + vector_bytes(x);
}

template <int Dim, typename Scalar>
void build_band_local(Level<Dim, Scalar>& level) {
  BandLocal<Dim, Scalar> local;
  number_variables(level, local);
  const auto shrink = [](auto&... v) { (v.shrink_to_fit(), ...); };
  shrink(local.self, local.first_column, local.pressure, local.column, local.gather.index);
  local.band_rows = level.band_kernel.rows();
  level.band_local = std::move(local);
}

template <int Dim, typename Scalar>
void band_local_sweeps(Level<Dim, Scalar>& level, int sweeps,
                       const typename Level<Dim, Scalar>::RowSchedule* rows) {
  BandLocal<Dim, Scalar>& local = level.band_local;
  Scalar* xl = local.x.data();
  const auto& gather = local.gather;
#pragma omp parallel
  for (int f = 0; f <= Dim; ++f) {
    const Scalar* xf = level.x[f].data();
#pragma omp for schedule(static) nowait
    for (std::ptrdiff_t i = gather.start[f]; i < static_cast<std::ptrdiff_t>(gather.start[f + 1]);
         ++i)
      xl[i] = xf[gather.index[i]];
  }
  const LocalSweep<Dim, Scalar> band{xl,
                                     level.band_kernel,
                                     local,
                                     level.band_blocks.data(),
                                     level.band_block_inverse.data(),
                                     level.band_block_inverse_id.data()};
  for (int sweep = 0; sweep < sweeps && rows; ++sweep) {
    for (const auto& color : *rows) {
      const auto count = static_cast<std::ptrdiff_t>(color.size());
#pragma omp parallel for schedule(dynamic, 1)
      for (std::ptrdiff_t b = 0; b < count; ++b)
        for (std::uint32_t m : color[b]) band.relax_row(m);
    }
  }
  for (int sweep = 0; sweep < sweeps && !rows; ++sweep) {
    // The blocks of one color touch disjoint variables (block_partition.hpp).
    for (const auto& color : level.band_schedule) {
      const auto count = static_cast<std::ptrdiff_t>(color.size());
#pragma omp parallel for schedule(dynamic, 1)
      for (std::ptrdiff_t b = 0; b < count; ++b) {
        for (std::uint32_t e : color[b].cell_blocks) band.relax_block(e);
        for (std::uint32_t m : color[b].point_rows) band.relax_row(m);
      }
    }
  }
  // Every gathered variable goes back (the read-only ones unchanged): the written ones share
  // their cache lines with them, and one list serves both directions.
#pragma omp parallel
  for (int f = 0; f <= Dim; ++f) {
    Scalar* xf = level.x[f].data();
#pragma omp for schedule(static) nowait
    for (std::ptrdiff_t i = gather.start[f]; i < static_cast<std::ptrdiff_t>(gather.start[f + 1]);
         ++i)
      xf[gather.index[i]] = xl[i];
  }
}

#define MGELASTIC_INSTANTIATE(D, S)                        \
  template struct BandLocal<D, S>;                         \
  template void build_band_local<D, S>(Level<D, S>&);      \
  template void band_local_sweeps<D, S>(Level<D, S>&, int, \
                                        const typename Level<D, S>::RowSchedule*);
MGELASTIC_INSTANTIATE(2, float)
MGELASTIC_INSTANTIATE(2, double)
MGELASTIC_INSTANTIATE(3, float)
MGELASTIC_INSTANTIATE(3, double)
#undef MGELASTIC_INSTANTIATE

}  // namespace mgelastic::grid
