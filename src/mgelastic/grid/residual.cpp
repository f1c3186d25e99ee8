#include "mgelastic/grid/residual.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "mgelastic/core/threads.hpp"
#include "mgelastic/grid/stencil.hpp"

namespace mgelastic::grid {
namespace {

// Entries per chunk of the stencil residual: the chunk's Dim + 1 residual rows (16 KiB in
// double at Dim = 3) stay in L1 between the evaluation and the masked copy.
constexpr std::ptrdiff_t residual_chunk = kLiveChunk;
static_assert(residual_chunk == 512);

// sum_{i < n} term(i) in eight partial sums, added pairwise at the end: a fixed order (the same
// value for any thread count) without one chain of dependent adds (~4 cycles per entry, which
// made the sums of squares a third of a residual pass).
template <typename Term>
double split_sum(std::ptrdiff_t n, const Term& term) {
  constexpr int kParts = 8;
  double part[kParts] = {};
  std::ptrdiff_t i = 0;
  for (; i + kParts <= n; i += kParts)
    for (int j = 0; j < kParts; ++j) part[j] += term(i + j);
  for (int j = 0; i < n; ++i, ++j) part[j] += term(i);
  return ((part[0] + part[1]) + (part[2] + part[3])) + ((part[4] + part[5]) + (part[6] + part[7]));
}

// Whether any field's equation in [begin, begin + m) is a stencil (DISTRIBUTIVE) row: one bit
// per field (Relaxation::DISTRIBUTIVE = 1 is the low bit of each relaxation pair).
template <int Dim>
bool any_distributive(const VarCode* codes, std::ptrdiff_t begin, std::ptrdiff_t m) {
  VarCode bits = 0;
  for (int f = 0; f <= Dim; ++f) bits |= relaxation_bits(f, Relaxation::DISTRIBUTIVE);
  return any_bits(codes + begin, m, bits);
}

// Stencil residuals of every field in one pass: each momentum row reads every u_j and p, so
// one pass streams x once instead of once per field (Dim + 1 times).
//   r_i = b_i - L_i(u, p) + c u_i   (momentum rows, DISTRIBUTIVE equations, else 0)
//   r_p = b_p - mu div u - (mu^2 / lambda) p   (pressure rows, DISTRIBUTIVE and lambda > 0)
// Layout: lattice.hpp's flat index k; the stencil reaches k -+ s[Dim - 1] at most, so every
// k in [s[Dim - 1], n - s[Dim - 1]) is evaluated and the padding plane at both ends is zeroed.
// Vectorization: the rows of a chunk of at most `residual_chunk` flat indices are evaluated
// unconditionally into a local buffer (no branch, no store that may alias the inputs: GCC
// vectorizes the loop), then copied out with a select on the relaxation class. Each row is the
// same expression as the point-wise residual, wherever a chunk starts, so r does not depend on
// the thread count or on the chunking.
template <int Dim, typename Scalar>
struct StencilResidual {
  std::array<const Scalar*, Dim> u;
  std::array<std::ptrdiff_t, Dim> s;
  StencilConstants<Dim, Scalar> c;
  const VarCode* codes;
  std::array<const Scalar*, Dim + 1> b;
  const Scalar* p;
  Scalar inertia, mu, d;
  bool has_pressure;
  std::ptrdiff_t lo, hi;  // the evaluated flat range (outside: padding planes, r = 0)

  explicit StencilResidual(const Level<Dim, Scalar>& level) {
    for (int i = 0; i < Dim; ++i) {
      u[i] = level.x[i].data();
      s[i] = level.lattice.stride(i);
    }
    const Scalar inv_h = static_cast<Scalar>(1.0 / level.lattice.h);
    c = {level.mu, inv_h, inv_h * inv_h};
    codes = level.codes.data();
    // A field recorded as zero (Level::zero_load) is read as nullptr: no read of its pages.
    for (int f = 0; f <= Dim; ++f) b[f] = level.zero_load[f] ? nullptr : level.b[f].data();
    p = level.x[Dim].data();
    inertia = level.inertia;
    mu = level.mu;
    has_pressure = level.lambda > 0;
    d = has_pressure ? level.mu * level.mu / level.lambda : Scalar(0);
    const auto n = static_cast<std::ptrdiff_t>(level.size());
    lo = std::min(s[Dim - 1], n);
    hi = std::max(n - s[Dim - 1], lo);
  }

  // Rows [begin, begin + m) with lo <= begin, begin + m <= hi and m <= residual_chunk into
  // r[f][k]; with `squares`, adds their sum of squares (unrounded, fixed order).
  template <typename Out>
  void chunk(const std::array<Out*, Dim + 1>& r, std::ptrdiff_t begin, std::ptrdiff_t m,
             double* squares) const {
    if (!any_distributive<Dim>(codes, begin, m)) {
      // Outside an embedded body (most of its bounding box) a chunk holds no stencil row: its
      // residuals are zero (as the select below would give) without reading x and b.
      for (int f = 0; f <= Dim; ++f) std::fill(r[f] + begin, r[f] + begin + m, Out(0));
      return;
    }
    // The chunk's loads, a zero field's from a block of zeros (in L1).
    alignas(64) static const Scalar zeros[residual_chunk] = {};
    std::array<const Scalar*, Dim + 1> load;
    for (int f = 0; f <= Dim; ++f) load[f] = b[f] ? b[f] + begin : zeros;
    alignas(64) Scalar value[Dim + 1][residual_chunk];
    for (std::ptrdiff_t i = 0; i < m; ++i) {
      const std::ptrdiff_t k = begin + i;
      value[0][i] = load[0][i] - momentum_row<Dim, Scalar, 0>(u, p, s, k, c) + inertia * u[0][k];
      value[1][i] = load[1][i] - momentum_row<Dim, Scalar, 1>(u, p, s, k, c) + inertia * u[1][k];
      if constexpr (Dim == 3)
        value[2][i] = load[2][i] - momentum_row<Dim, Scalar, 2>(u, p, s, k, c) + inertia * u[2][k];
      value[Dim][i] = load[Dim][i] - mu * divergence<Dim, Scalar>(u, s, k, c.inv_h) - d * p[k];
    }
    // Rows without a stencil equation are zeroed in the buffer, then the buffer is copied out
    // (rounded to Out) and summed: three loops that vectorize (a select on the code inside the
    // copy, with a shift by the field, kept it scalar).
    for (int f = 0; f <= Dim; ++f) {
      const VarCode* cf = codes + begin;
      Out* out = r[f] + begin;
      Scalar* v = value[f];
      if (f == Dim && !has_pressure) {
        std::fill(out, out + m, Out(0));
        continue;
      }
      const VarCode mask = relaxation_mask(f);
      const VarCode wanted = relaxation_bits(f, Relaxation::DISTRIBUTIVE);
#pragma omp simd
      for (std::ptrdiff_t i = 0; i < m; ++i) v[i] = (cf[i] & mask) == wanted ? v[i] : Scalar(0);
#pragma omp simd
      for (std::ptrdiff_t i = 0; i < m; ++i) out[i] = static_cast<Out>(v[i]);
      if (!squares) continue;
      *squares += split_sum(m, [&](std::ptrdiff_t i) { return static_cast<double>(v[i]) * v[i]; });
    }
  }
};

// The stencil rows of the whole level in fixed chunks of `residual_chunk` = kLiveChunk flat
// indices, in parallel; a dead chunk (live_chunks.hpp) is skipped, its r already zero. r[0]
// null: no residual array, each chunk's rows go to scratch on the stack (chunk_squares only).
template <int Dim, typename Scalar, typename Out>
void stencil_residual(const Level<Dim, Scalar>& level, const std::array<Out*, Dim + 1>& r,
                      std::vector<double>* chunk_squares) {
  const StencilResidual<Dim, Scalar> stencil(level);
  const bool write = r[0] != nullptr;
  const auto n = static_cast<std::ptrdiff_t>(level.size());
  const std::ptrdiff_t lo = stencil.lo, hi = stencil.hi;
  if (write)
    for (int f = 0; f <= Dim; ++f) {
      zero_live(r[f], 0, lo, level.live);
      zero_live(r[f], hi, n, level.live);
    }
  // Chunk q covers [q c, (q + 1) c) of the flat index clipped to [lo, hi).
  const std::ptrdiff_t first_chunk = lo / residual_chunk;
  const std::ptrdiff_t chunks = (hi + residual_chunk - 1) / residual_chunk - first_chunk;
  if (chunk_squares)
    chunk_squares->assign(static_cast<std::size_t>(std::max<std::ptrdiff_t>(chunks, 0)), 0.0);
  // Interleaved blocks of chunks (threads.hpp: an embedded body's live chunks are not spread
  // evenly over its bounding box).
  const std::ptrdiff_t block = interleaved_block(chunks);
#pragma omp parallel for schedule(static, block)
  for (std::ptrdiff_t q = 0; q < chunks; ++q) {
    const std::ptrdiff_t begin = std::max(lo, (first_chunk + q) * residual_chunk);
    const std::ptrdiff_t m = std::min((first_chunk + q + 1) * residual_chunk, hi) - begin;
    if (m <= 0 || !level.live.any_live(begin, begin + m)) continue;
    double* squares = chunk_squares ? &(*chunk_squares)[q] : nullptr;
    if (write) {
      stencil.chunk(r, begin, m, squares);
      continue;
    }
    alignas(64) Out scratch[Dim + 1][residual_chunk];
    std::array<Out*, Dim + 1> rows;
    for (int f = 0; f <= Dim; ++f) rows[f] = scratch[f] - begin;
    stencil.chunk(rows, begin, m, squares);
  }
}

// b at (field, k), without reading a field recorded as zero (Level::zero_load).
template <int Dim, typename Scalar>
Scalar load_at(const Level<Dim, Scalar>& level, int field, std::size_t k) {
  return level.zero_load[field] ? Scalar(0) : level.b[field][k];
}

// The residual of band momentum row m (compact form, band_kernel.hpp; the CSR rows may be
// dropped) and of band pressure row m (d0 = mu^2 / lambda).
// `addressed`: kernel.addressed_for(level.x) (the same sum, fewer instructions per entry).
template <int Dim, typename Scalar>
Scalar band_momentum_residual(const Level<Dim, Scalar>& level, std::size_t m,
                              bool addressed = false) {
  const BandKernel<Scalar>& kernel = level.band_kernel;
  const std::uint32_t k = kernel.target[m];
  const Scalar sum =
      addressed ? kernel.addressed_row_sum(level.x[0].data(), m) : kernel.row_sum(level.x, m);
  return load_at(level, kernel.field[m], k) - kernel.constant[m] - sum;
}
template <int Dim, typename Scalar>
Scalar band_pressure_residual(const Level<Dim, Scalar>& level, std::size_t m, Scalar d0,
                              bool addressed = false) {
  const SparseRows<Scalar>& rows = level.band_p;
  Scalar sum = 0;
  if (addressed) {
    sum = level.band_p_kernel.addressed_row_sum(level.x[0].data(), m);
  } else {
    for (std::uint32_t e = rows.start[m]; e < rows.start[m + 1]; ++e)
      sum += rows.value[e] * level.x[rows.column_field[e]][rows.column_index[e]];
  }
  const std::uint32_t k = rows.target_index[m];
  return load_at(level, Dim, k) - rows.constant[m] - sum -
         (d0 + level.band_p_extra[m]) * level.x[Dim][k];
}

// Whether band_pressure_residual may read level.band_p_kernel (built and addressed for x).
template <int Dim, typename Scalar>
bool pressure_rows_addressed(const Level<Dim, Scalar>& level) {
  return level.band_p_kernel.rows() == level.band_p.rows() &&
         level.band_p_kernel.addressed_for(level.x);
}

// The residuals of one line of band_row_planes.hpp (member a of a band run, rows
// rows[first_row + s * members + a]): visit(row, value) for each step. Each value is
// band_momentum_residual's: the same products added in the same entry order.
template <int Dim, typename Scalar, typename Visit>
void line_residuals(const Level<Dim, Scalar>& level, std::uint32_t line, const Visit& visit) {
  const BandKernel<Scalar>& kernel = level.band_kernel;
  const BandRuns<Dim, Scalar>& runs = level.band_runs;
  const BandRun& run = runs.runs[line / BandRowPlanes::kLineMembers];
  const int a = static_cast<int>(line % BandRowPlanes::kLineMembers);
  const BandRunShape<Dim, Scalar>& shape = runs.shapes[run.shape];
  const int length = static_cast<int>(run.length);
  const std::ptrdiff_t base = run.target + shape.offset[a];
  const std::ptrdiff_t stride = run.stride;
  const std::uint32_t p = shape.pattern[a];
  // Products rounded before they are added (row_sum's arithmetic: kept apart in their own
  // loop, so that no fused multiply-add forms).
  alignas(32) Scalar sum[kBandRunMaxLength] = {};
  alignas(32) Scalar product[kBandRunMaxLength];
  for (std::uint32_t e = kernel.start[p]; e < kernel.start[p + 1]; ++e) {
    const Scalar value = kernel.entry_value[e];
    const Scalar* __restrict xe =
        level.x[kernel.entry_field[e]].data() + base + kernel.entry_offset[e];
    if (stride == 1) {
#pragma omp simd
      for (int s = 0; s < length; ++s) product[s] = value * xe[s];
    } else {
      for (int s = 0; s < length; ++s) product[s] = value * xe[s * stride];
    }
#pragma omp simd
    for (int s = 0; s < length; ++s) sum[s] += product[s];
  }
  const std::uint32_t* rows = runs.rows.data() + run.first_row;
  for (int s = 0; s < length; ++s) {
    const std::uint32_t m = rows[s * shape.members + a];
    visit(m, load_at(level, kernel.field[m], kernel.target[m]) - kernel.constant[m] - sum[s]);
  }
}

// Band rows; with `squares`, also the sum of their squared residuals (before rounding to Out),
// added in row order. r[0] null: the squares only (nothing written). planes: the level's
// band_row_planes when valid (its lines are evaluated run-wise), else null.
template <int Dim, typename Scalar, typename Out>
void band_residual(const Level<Dim, Scalar>& level, const std::array<Out*, Dim + 1>& r,
                   double* squares, const BandRowPlanes* planes = nullptr) {
  const bool write = r[0] != nullptr;
  std::vector<Scalar> values;  // the rows' residuals, kept only when squares are asked for
  const auto keep = [&](std::size_t count) {
    if (squares) values.assign(count, Scalar(0));
  };
  const auto add_squares = [&] {
    for (Scalar v : values) *squares += static_cast<double>(v) * v;
  };
  const BandKernel<Scalar>& kernel = level.band_kernel;
  const bool addressed = kernel.addressed_for(level.x);
  keep(kernel.rows());
  const auto store = [&](std::uint32_t m, Scalar value) {
    if (write) r[kernel.field[m]][kernel.target[m]] = static_cast<Out>(value);
    if (squares) values[m] = value;
  };
  if (planes && planes->rows_in_lines > 0) {
    const auto lines = static_cast<std::ptrdiff_t>(planes->lines.size());
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < lines; ++i) line_residuals(level, planes->lines[i], store);
    const auto outside = static_cast<std::ptrdiff_t>(planes->momentum_rows.size());
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < outside; ++i) {
      const std::uint32_t m = planes->momentum_rows[i];
      store(m, band_momentum_residual(level, m, addressed));
    }
  } else {
    const auto u_count = static_cast<std::ptrdiff_t>(kernel.rows());
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t m = 0; m < u_count; ++m)
      store(static_cast<std::uint32_t>(m), band_momentum_residual(level, m, addressed));
  }
  if (squares) add_squares();
  if (level.lambda <= 0) return;
  const auto& p_rows = level.band_p;
  const bool addressed_p = pressure_rows_addressed(level);
  const Scalar d0 = level.mu * level.mu / level.lambda;
  const auto p_count = static_cast<std::ptrdiff_t>(p_rows.rows());
  keep(p_rows.rows());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t m = 0; m < p_count; ++m) {
    const Scalar value =
        band_pressure_residual(level, static_cast<std::size_t>(m), d0, addressed_p);
    if (write) r[Dim][p_rows.target_index[m]] = static_cast<Out>(value);
    if (squares) values[m] = value;
  }
  if (squares) add_squares();
}

// Sums of squares over fixed chunks in parallel, added in chunk order: the same value for any
// thread count.
template <int Dim, typename T>
double norm_of(const std::array<const T*, Dim + 1>& r, std::size_t size, const LiveChunks& live) {
  constexpr std::ptrdiff_t chunk = 1 << 14;
  const auto n = static_cast<std::ptrdiff_t>(size);
  const std::ptrdiff_t chunks_per_field = (n + chunk - 1) / chunk;
  std::vector<double> partial(static_cast<std::size_t>(chunks_per_field * (Dim + 1)));
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t q = 0; q < static_cast<std::ptrdiff_t>(partial.size()); ++q) {
    const T* field = r[q / chunks_per_field];
    const std::ptrdiff_t begin = (q % chunks_per_field) * chunk;
    const std::ptrdiff_t end = std::min(begin + chunk, n);
    if (!live.any_live(begin, end)) continue;  // zeros (live_chunks.hpp): partial[q] stays 0
    partial[q] = split_sum(end - begin, [&](std::ptrdiff_t i) {
      return static_cast<double>(field[begin + i]) * field[begin + i];
    });
  }
  double sum = 0.0;
  for (double value : partial) sum += value;
  return std::sqrt(sum);
}

}  // namespace

namespace {

// Stencil and band residuals into r (r[0] null: none written); with `squares`, their sum of
// squares (unrounded).
template <int Dim, typename Scalar, typename Out>
void level_residual(const Level<Dim, Scalar>& level, const std::array<Out*, Dim + 1>& r,
                    double* squares, const BandRowPlanes* planes = nullptr) {
  std::vector<double> chunk_squares;
  stencil_residual<Dim, Scalar, Out>(level, r, squares ? &chunk_squares : nullptr);
  if (squares)
    for (double value : chunk_squares) *squares += value;
  band_residual<Dim, Scalar, Out>(level, r, squares, planes);
}

}  // namespace

template <int Dim, typename Scalar>
void residual_planes(const Level<Dim, Scalar>& level, const BandRowPlanes& band_planes, int first,
                     int end, const std::array<Scalar*, Dim + 1>& r) {
  const StencilResidual<Dim, Scalar> stencil(level);
  const std::ptrdiff_t plane = level.lattice.stride(Dim - 1);
  const std::ptrdiff_t begin = first * plane, stop = end * plane;
  // Padding planes and dead chunks hold zeros (the window is scratch, so they are written).
  for (std::ptrdiff_t k = begin; k < stop;) {
    const std::ptrdiff_t next = std::min(stop, (k / residual_chunk + 1) * residual_chunk);
    const std::ptrdiff_t a = std::max(k, stencil.lo), e = std::min(next, stencil.hi);
    if (a < e && level.live.any_live(k, next)) {
      for (int f = 0; f <= Dim; ++f) {
        std::fill(r[f] + k, r[f] + a, Scalar(0));
        std::fill(r[f] + e, r[f] + next, Scalar(0));
      }
      stencil.chunk(r, a, e - a, nullptr);
    } else {
      for (int f = 0; f <= Dim; ++f) std::fill(r[f] + k, r[f] + next, Scalar(0));
    }
    k = next;
  }
  // The band rows of these planes overwrite their targets, as band_residual does.
  const BandKernel<Scalar>& kernel = level.band_kernel;
  if (band_planes.rows_in_lines > 0)
    for (std::uint32_t i = band_planes.line_start[first]; i < band_planes.line_start[end]; ++i)
      line_residuals(level, band_planes.lines[i], [&](std::uint32_t m, Scalar value) {
        r[kernel.field[m]][kernel.target[m]] = value;
      });
  const bool addressed = kernel.addressed_for(level.x);
  for (std::uint32_t i = band_planes.momentum_start[first]; i < band_planes.momentum_start[end];
       ++i) {
    const std::uint32_t m = band_planes.momentum_rows[i];
    r[kernel.field[m]][kernel.target[m]] = band_momentum_residual(level, m, addressed);
  }
  if (level.lambda <= 0) return;
  const auto& p_rows = level.band_p;
  const bool addressed_p = pressure_rows_addressed(level);
  const Scalar d0 = level.mu * level.mu / level.lambda;
  for (std::uint32_t i = band_planes.pressure_start[first]; i < band_planes.pressure_start[end];
       ++i) {
    const std::uint32_t m = band_planes.pressure_rows[i];
    r[Dim][p_rows.target_index[m]] = band_pressure_residual(level, m, d0, addressed_p);
  }
}

template <int Dim, typename Scalar, typename Out>
double residual_into(const Level<Dim, Scalar>& level, const std::array<Out*, Dim + 1>& r) {
  double squares = 0;
  level_residual<Dim, Scalar, Out>(level, r, &squares);
  return std::sqrt(squares);
}

template <int Dim, typename Scalar>
double fresh_residual_norm(const Level<Dim, Scalar>& level, const BandRowPlanes* band_planes) {
  double squares = 0;
  const BandRowPlanes* planes =
      band_planes && band_planes->valid_for(level) ? band_planes : nullptr;
  level_residual<Dim, Scalar, Scalar>(level, {}, &squares, planes);  // null arrays: squares only
  return std::sqrt(squares);
}

template <int Dim, typename Scalar>
void update_residual(Level<Dim, Scalar>& level) {
  ensure_residual_storage(level);
  std::array<Scalar*, Dim + 1> r;
  for (int f = 0; f <= Dim; ++f) r[f] = level.r[f].data();
  level_residual<Dim, Scalar, Scalar>(level, r, nullptr);
}

template <int Dim, typename Scalar>
double compute_residual(Level<Dim, Scalar>& level) {
  update_residual(level);
  return residual_norm(level);
}

template <int Dim, typename Scalar>
double residual_norm(const Level<Dim, Scalar>& level) {
  std::array<const Scalar*, Dim + 1> r;
  for (int f = 0; f <= Dim; ++f) r[f] = level.r[f].data();
  return norm_of<Dim, Scalar>(r, level.size(), level.live);
}

template <int Dim, typename Scalar>
void stencil_residual_at(const Level<Dim, Scalar>& level, const std::vector<Stretch>& stretches,
                         const std::array<double*, Dim + 1>& r) {
  const StencilResidual<Dim, Scalar> stencil(level);
  std::vector<std::size_t> offset(stretches.size() + 1, 0);
  for (std::size_t i = 0; i < stretches.size(); ++i)
    offset[i + 1] = offset[i] + stretches[i].length;
  const auto count = static_cast<std::ptrdiff_t>(stretches.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < count; ++i) {
    const std::ptrdiff_t k = stretches[i].first;
    const auto length = static_cast<std::ptrdiff_t>(stretches[i].length);
    std::array<double*, Dim + 1> out;  // out[f][k] = r[f][offset[i]]
    for (int f = 0; f <= Dim; ++f) out[f] = r[f] + offset[i] - k;
    // Points outside the evaluated range (padding planes) hold no stencil row.
    const std::ptrdiff_t a = std::clamp(stencil.lo, k, k + length);
    const std::ptrdiff_t e = std::clamp(stencil.hi, a, k + length);
    for (int f = 0; f <= Dim; ++f) {
      std::fill(out[f] + k, out[f] + a, 0.0);
      std::fill(out[f] + e, out[f] + k + length, 0.0);
    }
    for (std::ptrdiff_t c = a; c < e; c += residual_chunk)
      stencil.chunk(out, c, std::min(residual_chunk, e - c), nullptr);
  }
}

template <int Dim, typename Scalar>
void band_residual_at(const Level<Dim, Scalar>& level, const std::vector<std::uint32_t>& rows,
                      double* out) {
  for (std::size_t i = 0; i < rows.size(); ++i)
    out[i] = static_cast<double>(band_momentum_residual(level, rows[i]));
}

template <int Dim, typename Scalar>
void band_pressure_residual_at(const Level<Dim, Scalar>& level,
                               const std::vector<std::uint32_t>& rows, double* out) {
  const Scalar d0 = level.lambda > 0 ? level.mu * level.mu / level.lambda : Scalar(0);
  for (std::size_t i = 0; i < rows.size(); ++i)
    out[i] = static_cast<double>(band_pressure_residual(level, rows[i], d0));
}

#define MGELASTIC_INSTANTIATE(D, S)                                                           \
  template void stencil_residual_at<D, S>(const Level<D, S>&, const std::vector<Stretch>&,    \
                                          const std::array<double*, D + 1>&);                 \
  template void band_residual_at<D, S>(const Level<D, S>&, const std::vector<std::uint32_t>&, \
                                       double*);                                              \
  template void band_pressure_residual_at<D, S>(const Level<D, S>&,                           \
                                                const std::vector<std::uint32_t>&, double*);  \
  template void residual_planes<D, S>(const Level<D, S>&, const BandRowPlanes&, int, int,     \
                                      const std::array<S*, D + 1>&);                          \
  template void update_residual<D, S>(Level<D, S>&);                                          \
  template double compute_residual<D, S>(Level<D, S>&);                                       \
  template double fresh_residual_norm<D, S>(const Level<D, S>&, const BandRowPlanes*);        \
  template double residual_norm<D, S>(const Level<D, S>&);                                    \
  template double residual_into<D, double, S>(const Level<D, double>&,                        \
                                              const std::array<S*, D + 1>&);

MGELASTIC_INSTANTIATE(2, float)
MGELASTIC_INSTANTIATE(2, double)
MGELASTIC_INSTANTIATE(3, float)
MGELASTIC_INSTANTIATE(3, double)
#undef MGELASTIC_INSTANTIATE

}  // namespace mgelastic::grid
