#include "mgelastic/grid/band_runs.hpp"

#include <algorithm>
#include <cstring>
#include <numeric>
#include <string>
#include <unordered_map>

#include "mgelastic/core/bytes.hpp"
#include "mgelastic/grid/level.hpp"

namespace mgelastic::grid {
namespace {

// One step of a block's sweep: a cell block (members solved together) or the point rows of one
// location (relaxed in order).
template <int Dim>
struct Step {
  bool cell_block = false;
  std::uint32_t index = 0;  // band_blocks index, or 0 for a point group
  int members = 0;
  std::array<std::uint32_t, 2 * Dim> rows{};
};

template <int Dim, typename Scalar>
std::ptrdiff_t step_target(const Level<Dim, Scalar>& level, const Step<Dim>& step) {
  return level.band_kernel.target[step.rows[0]];
}

// Bytes that identify a step's shape: equal keys give equal couplings and weights.
template <int Dim, typename Scalar>
void shape_key(const Level<Dim, Scalar>& level, const Step<Dim>& step, std::ptrdiff_t stride,
               std::string& key) {
  constexpr int G = 2 * Dim;
  const auto& kernel = level.band_kernel;
  key.clear();
  append_bytes(key, stride);
  append_bytes(key, step.cell_block);
  append_bytes(key, step.members);
  const std::ptrdiff_t self = step_target(level, step);
  for (int a = 0; a < step.members; ++a) {
    const std::uint32_t m = step.rows[a];
    append_bytes(key, kernel.pattern[m]);
    append_bytes(key, kernel.field[m]);
    append_bytes(key, static_cast<std::int32_t>(kernel.target[m] - self));
  }
  if (step.cell_block)
    key.append(reinterpret_cast<const char*>(level.block_inverse(step.index)),
               G * G * sizeof(Scalar));
}

// Couplings, weights and reach of a step's shape (see band_runs.hpp), summed in double.
template <int Dim, typename Scalar>
BandRunShape<Dim, Scalar> make_shape(const Level<Dim, Scalar>& level, const Step<Dim>& step,
                                     std::ptrdiff_t stride) {
  constexpr int G = 2 * Dim;
  const auto& kernel = level.band_kernel;
  BandRunShape<Dim, Scalar> shape;
  shape.members = step.members;
  const std::ptrdiff_t self = step_target(level, step);
  for (int a = 0; a < step.members; ++a) {
    const std::uint32_t m = step.rows[a];
    shape.pattern[a] = kernel.pattern[m];
    shape.field[a] = kernel.field[m];
    shape.offset[a] = static_cast<std::int32_t>(kernel.target[m] - self);
  }
  // coupling[j][a][b]: d r_a(step s) / d delta_b(step s - j), for j < kBandRunMaxLength. Step
  // s - j lies j * stride entries before step s; reads between the steps' lines couple to none.
  std::vector<std::array<double, G * G>> coupling(kBandRunMaxLength, std::array<double, G * G>{});
  auto add = [&](std::ptrdiff_t distance, int a, int b, double value) {
    if (distance % stride != 0) return;
    const std::ptrdiff_t lag = distance / stride;
    if (lag >= 0 && lag < kBandRunMaxLength) coupling[lag][a * G + b] += value;
  };
  for (int a = 0; a < step.members; ++a) {
    const std::uint32_t pa = shape.pattern[a];
    for (std::uint32_t e = kernel.start[pa]; e < kernel.start[pa + 1]; ++e) {
      const std::ptrdiff_t read = shape.offset[a] + kernel.entry_offset[e];
      const double value = kernel.entry_value[e];
      for (int b = 0; b < step.members; ++b) {
        const std::uint32_t pb = shape.pattern[b];
        if (kernel.entry_field[e] == shape.field[b]) add(shape.offset[b] - read, a, b, value);
        if (kernel.entry_field[e] != Dim) continue;
        for (int c = 0; c < kernel.pressure_count[pb]; ++c)
          add(shape.offset[b] + kernel.pressure_offset[pb][c] - read, a, b,
              -value * static_cast<double>(kernel.pressure_factor[pb][c]));
      }
    }
  }
  // Couplings beyond kBandRunMaxLag steps cap the run below them; the others enter A_j below.
  for (int lag = kBandRunMaxLag + 1; lag < kBandRunMaxLength; ++lag) {
    const bool coupled =
        std::any_of(coupling[lag].begin(), coupling[lag].end(), [](double v) { return v != 0; });
    if (coupled) shape.max_length = std::min(shape.max_length, lag);
  }
  if (step.cell_block) {
    std::copy_n(level.block_inverse(step.index), G * G, shape.weight.begin());
  } else {
    // Point group: row a sees the earlier rows of its location, (D + L_0) delta = r0; W is its
    // inverse, by forward substitution on the unit vectors.
    const int g = step.members;
    for (int col = 0; col < g; ++col) {
      std::array<double, G> w{};
      for (int a = 0; a < g; ++a) {
        double rhs = a == col ? 1.0 : 0.0;
        for (int b = 0; b < a; ++b) rhs -= coupling[0][a * G + b] * w[b];
        w[a] = rhs / static_cast<double>(kernel.schur_diagonal[shape.pattern[a]]);
      }
      for (int a = 0; a < g; ++a) shape.weight[a * G + col] = static_cast<Scalar>(w[a]);
    }
  }
  // A_j = W C_j, in double from the stored W (zero where step s - j does not couple).
  for (int j = 1; j <= kBandRunMaxLag; ++j)
    for (int a = 0; a < G; ++a)
      for (int b = 0; b < G; ++b) {
        double sum = 0;
        for (int c = 0; c < G; ++c)
          sum += static_cast<double>(shape.weight[a * G + c]) * coupling[j][c * G + b];
        shape.lag_response[j - 1][a * G + b] = static_cast<Scalar>(sum);
      }
  return shape;
}

template <int Dim, typename Scalar>
std::vector<Step<Dim>> block_steps(const Level<Dim, Scalar>& level,
                                   const std::vector<std::uint32_t>& cell_blocks,
                                   const std::vector<std::uint32_t>& point_rows) {
  std::vector<Step<Dim>> steps;
  for (std::uint32_t e : cell_blocks) {
    Step<Dim> step;
    step.cell_block = true;
    step.index = e;
    for (std::uint32_t m : level.band_blocks[e]) {
      if (m == UINT32_MAX) break;
      step.rows[step.members++] = m;
    }
    steps.push_back(step);
  }
  const auto& target = level.band_kernel.target;
  for (std::size_t i = 0; i < point_rows.size();) {
    Step<Dim> step;
    const std::uint32_t first = point_rows[i];
    while (i < point_rows.size() && target[point_rows[i]] == target[first])
      step.rows[step.members++] = point_rows[i++];
    steps.push_back(step);
  }
  return steps;
}

// Sort key of a step off the x-runs: its lattice coordinates with y fastest, then x, then z.
template <int Dim, typename Scalar>
std::array<int, Dim> across_order(const Level<Dim, Scalar>& level, const Step<Dim>& step) {
  const IVec<Dim> s = level.lattice.coords(step_target(level, step));
  std::array<int, Dim> key{};
  for (int a = 2; a < Dim; ++a) key[Dim - 1 - a] = s[a];
  key[Dim - 2] = s[0];
  key[Dim - 1] = s[1];
  return key;
}

// The sweeps read only the shapes of runs. Every step got a shape while the runs were found; on a
// curved band most steps are off the runs with shapes of their own (armadillo at 256: ~90 % of
// the shapes, 16.8 of its 350 bytes per unknown), so those are dropped and the runs renumbered.
template <int Dim, typename Scalar>
void drop_shapes_off_runs(BandRuns<Dim, Scalar>& runs) {
  std::vector<std::uint32_t> kept(runs.shapes.size(), UINT32_MAX);
  std::vector<BandRunShape<Dim, Scalar>> shapes;
  for (BandRun& run : runs.runs) {
    if (kept[run.shape] == UINT32_MAX) {
      kept[run.shape] = static_cast<std::uint32_t>(shapes.size());
      shapes.push_back(runs.shapes[run.shape]);
    }
    run.shape = kept[run.shape];
  }
  runs.shapes = std::move(shapes);
  runs.runs.shrink_to_fit();  // grown by push_back: up to half of each allocation unused
  runs.rows.shrink_to_fit();
}

}  // namespace

template <int Dim, typename Scalar>
std::size_t BandRuns<Dim, Scalar>::bytes() const {
  std::size_t total = vector_bytes(shapes) + vector_bytes(runs) + vector_bytes(rows);
  for (const auto& color : schedule)
    for (const auto& block : color) total += vector_bytes(block);
  return total;
}

template <int Dim, typename Scalar>
std::size_t band_block_work(const Level<Dim, Scalar>& level, const BandRuns<Dim, Scalar>& runs,
                            const std::vector<std::uint32_t>& items) {
  std::size_t work = 0;
  for (const std::uint32_t item : items) {
    const std::uint32_t index = item & kBandItemIndexMask;
    switch (static_cast<BandItem>(item & ~kBandItemIndexMask)) {
      case BandItem::RUN:
        work += runs.runs[index].length *
                static_cast<std::size_t>(runs.shapes[runs.runs[index].shape].members);
        break;
      case BandItem::CELL_BLOCK:
        for (const std::uint32_t row : level.band_blocks[index]) work += row != UINT32_MAX;
        break;
      case BandItem::POINT_ROW:
        work += 1;
        break;
    }
  }
  return work;
}

namespace {

// The blocks of one color are independent, and the sweeps hand them to the threads one at a time
// in schedule order: largest first, so that a thread's last block of a color is a small one and
// the other does not wait at the color's barrier for a block full of band faces (the box's
// blocks on its walls hold ~8x the band rows of those that only touch the x-ends); blocks
// without band work are left out. Results are unchanged (independent blocks, fixed inner order).
template <int Dim, typename Scalar>
void largest_first(const Level<Dim, Scalar>& level, BandRuns<Dim, Scalar>& runs) {
  for (auto& color : runs.schedule) {
    std::vector<std::pair<std::size_t, std::size_t>> order;  // (work, block)
    for (std::size_t w = 0; w < color.size(); ++w)
      if (const std::size_t work = band_block_work(level, runs, color[w]); work > 0)
        order.push_back({work, w});
    std::stable_sort(order.begin(), order.end(),
                     [](const auto& a, const auto& b) { return a.first > b.first; });
    std::vector<std::vector<std::uint32_t>> sorted;
    sorted.reserve(order.size());
    for (const auto& [work, w] : order) sorted.push_back(std::move(color[w]));
    color = std::move(sorted);
  }
}

}  // namespace

template <int Dim, typename Scalar>
void build_band_runs(Level<Dim, Scalar>& level) {
  BandRuns<Dim, Scalar> runs;
  std::unordered_map<std::string, std::uint32_t> ids;
  std::string key;
  const std::ptrdiff_t across = level.lattice.stride(1);
  // A shape's couplings and weights are formed when a run needs them: on a curved band most
  // steps are alone with their shape (see drop_shapes_off_runs), and so are most on the
  // coarse levels, whose weighted rows seldom repeat.
  std::vector<std::pair<Step<Dim>, std::ptrdiff_t>> first_step;  // per key id
  std::vector<std::uint32_t> shape_index;  // per key id: its runs.shapes entry, once formed
  auto shape_id = [&](const Step<Dim>& step, std::ptrdiff_t stride) {
    shape_key(level, step, stride, key);
    const auto [it, added] = ids.try_emplace(key, static_cast<std::uint32_t>(ids.size()));
    if (added) {
      first_step.emplace_back(step, stride);
      shape_index.push_back(UINT32_MAX);
    }
    return it->second;
  };
  // The runs.shapes entry of key id, formed on first use.
  auto shape = [&](std::uint32_t id) {
    if (shape_index[id] == UINT32_MAX) {
      shape_index[id] = static_cast<std::uint32_t>(runs.shapes.size());
      runs.shapes.push_back(make_shape(level, first_step[id].first, first_step[id].second));
    }
    return shape_index[id];
  };
  // Greedy maximal runs: length[i] > 0 where a sequence of equally shaped steps `stride` apart
  // starts (shorter than kBandRunMinLength: relaxed step by step), 0 inside one.
  auto find_runs = [&](const std::vector<Step<Dim>>& steps, std::ptrdiff_t stride,
                       std::vector<std::uint32_t>& shape_of) {
    shape_of.resize(steps.size());
    for (std::size_t i = 0; i < steps.size(); ++i) shape_of[i] = shape_id(steps[i], stride);
    std::vector<std::size_t> length(steps.size(), 0);
    for (std::size_t i = 0; i < steps.size();) {
      std::size_t end = i + 1;
      while (end < steps.size() && shape_of[end] == shape_of[i] &&
             static_cast<int>(end - i) < runs.shapes[shape(shape_of[i])].max_length &&
             step_target(level, steps[end]) == step_target(level, steps[end - 1]) + stride)
        ++end;
      length[i] = end - i;
      i = end;
    }
    return length;
  };
  // Appends the items of `steps` (runs `stride` apart, other steps one by one) and the steps in
  // item order.
  auto emit = [&](const std::vector<Step<Dim>>& steps, std::ptrdiff_t stride,
                  std::vector<std::uint32_t>& items, std::vector<Step<Dim>>& order) {
    std::vector<std::uint32_t> shape_of;
    const std::vector<std::size_t> length = find_runs(steps, stride, shape_of);
    for (std::size_t i = 0; i < steps.size(); i += length[i]) {
      const std::size_t end = i + length[i];
      const int members = steps[i].members;  // the shape's (equal keys, equal members)
      const bool run = static_cast<int>(length[i]) >= kBandRunMinLength;
      runs.steps += length[i];
      runs.row_relaxations += length[i] * members;
      if (run) {
        runs.steps_in_runs += length[i];
        runs.row_relaxations_in_runs += length[i] * members;
        items.push_back(static_cast<std::uint32_t>(BandItem::RUN) |
                        static_cast<std::uint32_t>(runs.runs.size()));
        runs.runs.push_back({shape(shape_of[i]), static_cast<std::uint32_t>(length[i]),
                             static_cast<std::uint32_t>(runs.rows.size()),
                             step_target(level, steps[i]), stride});
        for (std::size_t s = i; s < end; ++s)
          runs.rows.insert(runs.rows.end(), steps[s].rows.begin(),
                           steps[s].rows.begin() + steps[s].members);
      } else {
        for (std::size_t s = i; s < end; ++s) {
          if (steps[s].cell_block) {
            items.push_back(static_cast<std::uint32_t>(BandItem::CELL_BLOCK) | steps[s].index);
          } else {
            for (int a = 0; a < steps[s].members; ++a)
              items.push_back(static_cast<std::uint32_t>(BandItem::POINT_ROW) | steps[s].rows[a]);
          }
        }
      }
      order.insert(order.end(), steps.begin() + i, steps.begin() + end);
    }
  };
  // The steps of x-runs keep their order; then the runs along y among the others (faces across
  // x, where the band is a few cells thick in x), found with y fastest; then the remaining steps
  // in their original order (sorting them too cost the embedded shapes' bands their locality).
  auto add_items = [&](const std::vector<Step<Dim>>& steps, std::vector<std::uint32_t>& items,
                       std::vector<Step<Dim>>& order) {
    std::vector<std::uint32_t> shape_of;
    const std::vector<std::size_t> length = find_runs(steps, 1, shape_of);
    std::vector<Step<Dim>> along_x, rest;
    for (std::size_t i = 0; i < steps.size(); i += length[i]) {
      auto& to = static_cast<int>(length[i]) >= kBandRunMinLength ? along_x : rest;
      to.insert(to.end(), steps.begin() + i, steps.begin() + i + length[i]);
    }
    std::vector<std::size_t> sorted(rest.size());
    std::iota(sorted.begin(), sorted.end(), std::size_t{0});
    std::stable_sort(sorted.begin(), sorted.end(), [&](std::size_t a, std::size_t b) {
      return across_order(level, rest[a]) < across_order(level, rest[b]);
    });
    std::vector<Step<Dim>> by_y(rest.size());
    for (std::size_t i = 0; i < sorted.size(); ++i) by_y[i] = rest[sorted[i]];
    const std::vector<std::size_t> y_length = find_runs(by_y, across, shape_of);
    std::vector<Step<Dim>> along_y, others;
    std::vector<std::uint8_t> in_y_run(rest.size(), 0);
    for (std::size_t i = 0; i < by_y.size(); i += y_length[i]) {
      if (static_cast<int>(y_length[i]) < kBandRunMinLength) continue;
      along_y.insert(along_y.end(), by_y.begin() + i, by_y.begin() + i + y_length[i]);
      for (std::size_t j = i; j < i + y_length[i]; ++j) in_y_run[sorted[j]] = 1;
    }
    for (std::size_t i = 0; i < rest.size(); ++i)
      if (!in_y_run[i]) others.push_back(rest[i]);
    emit(along_x, 1, items, order);
    emit(along_y, across, items, order);
    emit(others, 1, items, order);
  };
  for (int c = 0; c < (1 << Dim); ++c) {
    runs.schedule[c].resize(level.band_schedule[c].size());
    for (std::size_t w = 0; w < level.band_schedule[c].size(); ++w) {
      auto& work = level.band_schedule[c][w];
      std::vector<Step<Dim>> order;
      auto& items = runs.schedule[c][w];
      add_items(block_steps(level, work.cell_blocks, {}), items, order);
      add_items(block_steps(level, {}, work.point_rows), items, order);
      // The step-by-step sweep takes the same order.
      work.cell_blocks.clear();
      work.point_rows.clear();
      for (const Step<Dim>& step : order) {
        if (step.cell_block)
          work.cell_blocks.push_back(step.index);
        else
          work.point_rows.insert(work.point_rows.end(), step.rows.begin(),
                                 step.rows.begin() + step.members);
      }
    }
  }
  largest_first(level, runs);
  drop_shapes_off_runs(runs);
  runs.band_rows = level.band_kernel.rows();
  level.band_runs = std::move(runs);
}

namespace {

// relax_band_run for runs of M members with the steps `stride` apart (Contiguous: 1, loads and
// stores vectorize). M is a template argument so that the recurrence's small matrices live in
// registers.
// The loops over a run's steps go in chunks of kRunChunk steps. Left to the compiler, the vector
// loop takes 32 steps a trip and leaves up to 31 to scalar code, and the runs are 8-64 steps long.
// A run of at least one chunk ends with a chunk shifted back to end at its last step, whose lanes
// before `from` (done by the chunk before) add zero; shorter runs go step by step.
inline constexpr int kRunChunk = 8;  // steps per vector trip (8 floats in 32 bytes)
static_assert(kBandRunMaxLength % kRunChunk == 0);

// Calls chunk(s0, from) for the chunks of steps s0..s0 + kRunChunk - 1 covering 0..length - 1;
// a chunk must leave the steps before `from` unchanged.
template <typename Chunk>
inline void for_each_chunk(int length, Chunk&& chunk) {
  if (length < kRunChunk) return;
  const int whole = length / kRunChunk * kRunChunk;
  for (int s0 = 0; s0 < whole; s0 += kRunChunk) chunk(s0, s0);
  if (whole < length) chunk(length - kRunChunk, whole);
}

// First step left to the step-by-step loop after for_each_chunk: none for runs of a chunk or
// more.
inline int tail_start(int length) {
  return length < kRunChunk ? 0 : length;
}

template <bool Contiguous, int M, int Dim, typename Scalar>
void relax_run(const std::array<Scalar*, Dim + 1>& x, const BandKernel<Scalar>& kernel,
               const BandRunShape<Dim, Scalar>& shape, const BandRun& run,
               const std::uint32_t* rows) {
  const std::ptrdiff_t stride = Contiguous ? 1 : run.stride;
  constexpr int G = 2 * Dim;
  constexpr int K = kBandRunMaxLag;
  static_assert(K == 2, "the recurrence below spells out the lags A_1 (near) and A_2 (far)");
  const int length = static_cast<int>(run.length);
  const std::uint32_t* run_rows = rows + run.first_row;
  // Pass 1: every member's residual at every step from the values before the run, summed in
  // the pattern's entry order like the step-by-step sweep.
  const int padded = (length + kRunChunk - 1) / kRunChunk * kRunChunk;
  alignas(32) Scalar r[M][kBandRunMaxLength];
  for (int a = 0; a < M; ++a) {
    alignas(32) Scalar sum[kBandRunMaxLength] = {};
    const std::ptrdiff_t base = run.target + shape.offset[a];
    const std::uint32_t p = shape.pattern[a];
    for (std::uint32_t e = kernel.start[p]; e < kernel.start[p + 1]; ++e) {
      const Scalar value = kernel.entry_value[e];
      const Scalar* __restrict xe = x[kernel.entry_field[e]] + base + kernel.entry_offset[e];
      for_each_chunk(length, [&](int s0, int from) {
#pragma omp simd
        for (int i = 0; i < kRunChunk; ++i) {
          const int s = s0 + i;
          const Scalar term = value * xe[s * stride];
          sum[s] += s >= from ? term : Scalar(0);
        }
      });
      for (int s = tail_start(length); s < length; ++s) sum[s] += value * xe[s * stride];
    }
    for (int s = 0; s < length; ++s) r[a][s] = kernel.rhs[run_rows[s * M + a]] - sum[s];
    for (int s = length; s < padded; ++s) r[a][s] = 0;
  }
  // Pass 2: delta_s = W r0_s for every step (vectorized), then the recurrence
  // delta_s -= A_1 delta_{s-1} + A_2 delta_{s-2} (delta[.][K + s] is step s).
  alignas(32) Scalar delta[M][K + kBandRunMaxLength];
  for (int a = 0; a < M; ++a) {
    for (int j = 0; j < K; ++j) delta[a][j] = 0;
    Scalar* __restrict d = delta[a] + K;
    const Scalar* w = shape.weight.data() + a * G;
    for (int s0 = 0; s0 < padded; s0 += kRunChunk) {
#pragma omp simd
      for (int i = 0; i < kRunChunk; ++i) {
        Scalar sum = 0;
        for (int b = 0; b < M; ++b) sum += w[b] * r[b][s0 + i];
        d[s0 + i] = sum;
      }
    }
  }
  Scalar response[K][M][M];
  for (int j = 0; j < K; ++j)
    for (int a = 0; a < M; ++a)
      for (int b = 0; b < M; ++b) response[j][a][b] = shape.lag_response[j][a * G + b];
  for (int s = 0; s < length; ++s) {
    Scalar earlier[K][M];
    for (int j = 0; j < K; ++j)
      for (int b = 0; b < M; ++b) earlier[j][b] = delta[b][K + s - 1 - j];
    for (int a = 0; a < M; ++a) {
      Scalar far = 0, near = 0;
      for (int b = 0; b < M; ++b) far += response[1][a][b] * earlier[1][b];
      for (int b = 0; b < M; ++b) near += response[0][a][b] * earlier[0][b];
      delta[a][K + s] -= far + near;
    }
  }
  // Pass 3: move every member's variable and keep its eliminated pressures exact.
  for (int a = 0; a < M; ++a) {
    const std::ptrdiff_t base = run.target + shape.offset[a];
    const Scalar* __restrict d = delta[a] + K;
    Scalar* __restrict xa = x[shape.field[a]] + base;
    for_each_chunk(length, [&](int s0, int from) {
#pragma omp simd
      for (int i = 0; i < kRunChunk; ++i) {
        const int s = s0 + i;
        xa[s * stride] += s >= from ? d[s] : Scalar(0);
      }
    });
    for (int s = tail_start(length); s < length; ++s) xa[s * stride] += d[s];
    const std::uint32_t p = shape.pattern[a];
    for (int c = 0; c < kernel.pressure_count[p]; ++c) {
      const Scalar factor = kernel.pressure_factor[p][c];
      Scalar* __restrict pa = x[Dim] + base + kernel.pressure_offset[p][c];
      for_each_chunk(length, [&](int s0, int from) {
#pragma omp simd
        for (int i = 0; i < kRunChunk; ++i) {
          const int s = s0 + i;
          pa[s * stride] -= s >= from ? factor * d[s] : Scalar(0);
        }
      });
      for (int s = tail_start(length); s < length; ++s) pa[s * stride] -= factor * d[s];
    }
  }
}

template <bool Contiguous, int Dim, typename Scalar>
void relax_run_of(const std::array<Scalar*, Dim + 1>& x, const BandKernel<Scalar>& kernel,
                  const BandRunShape<Dim, Scalar>& shape, const BandRun& run,
                  const std::uint32_t* rows) {
  switch (shape.members) {
    case 1:
      return relax_run<Contiguous, 1>(x, kernel, shape, run, rows);
    case 2:
      return relax_run<Contiguous, 2>(x, kernel, shape, run, rows);
    case 3:
      return relax_run<Contiguous, 3>(x, kernel, shape, run, rows);
    case 4:
      return relax_run<Contiguous, 4>(x, kernel, shape, run, rows);
    default:
      break;
  }
  if constexpr (Dim == 3) {
    if (shape.members == 5) return relax_run<Contiguous, 5>(x, kernel, shape, run, rows);
    return relax_run<Contiguous, 6>(x, kernel, shape, run, rows);
  }
}

}  // namespace

template <int Dim, typename Scalar>
void relax_band_run(const std::array<Scalar*, Dim + 1>& x, const BandKernel<Scalar>& kernel,
                    const BandRunShape<Dim, Scalar>& shape, const BandRun& run,
                    const std::uint32_t* rows) {
  if (run.stride == 1)
    relax_run_of<true>(x, kernel, shape, run, rows);
  else
    relax_run_of<false>(x, kernel, shape, run, rows);
}

#define MGELASTIC_INSTANTIATE(D, S)                                                      \
  template struct BandRuns<D, S>;                                                        \
  template void build_band_runs<D, S>(Level<D, S>&);                                     \
  template std::size_t band_block_work<D, S>(const Level<D, S>&, const BandRuns<D, S>&,  \
                                             const std::vector<std::uint32_t>&);         \
  template void relax_band_run<D, S>(const std::array<S*, D + 1>&, const BandKernel<S>&, \
                                     const BandRunShape<D, S>&, const BandRun&,          \
                                     const std::uint32_t*);
MGELASTIC_INSTANTIATE(2, float)
MGELASTIC_INSTANTIATE(2, double)
MGELASTIC_INSTANTIATE(3, float)
MGELASTIC_INSTANTIATE(3, double)
#undef MGELASTIC_INSTANTIATE

}  // namespace mgelastic::grid
