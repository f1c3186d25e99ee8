#pragma once
// What the grid kernel benchmarks run on, built once per process and cycled twice so every level
// holds a non-trivial right-hand side and correction (float levels under a double solution
// level, the V-cycle's defaults, nu = 0.48):
//   body 0  the paper's mixed box (Sec. 9.1; the lowest eighth clamped) of `cells` per axis;
//   body 1  the armadillo of $MGELASTIC_DATA_DIR voxelized at `cells` along its longest axis
//           (lowest 5 % fixed, gravity, one extra band layer: `mgelastic bench vcycle --mesh`).
// Counters are per active (INTERIOR) cell of the finest level, issue 24's measure of embedded
// bodies against the box.
//
// Cold runs: a kernel inside a V-cycle finds little of its data in cache (the passes between two
// calls stream the level's fields), so `cold` benchmarks evict the caches before each call
// (outside the timing) by writing a buffer twice the last-level cache.
#include <benchmark/benchmark.h>

#include <memory>
#include <string>

#include "mgelastic/grid/multigrid.hpp"

namespace mgelastic::bench {

struct BenchHierarchy {
  grid::ElasticityProblem<3> problem;
  std::unique_ptr<grid::Multigrid<3, float>> multigrid;
  std::size_t active_cells = 0;
  std::string error;  // why it could not be built (multigrid null)
};

const BenchHierarchy& hierarchy(int body, int cells);

// The hierarchy of the benchmark's arguments (body, cells, cold), or null after skipping the
// benchmark with the reason (no $MGELASTIC_DATA_DIR, a missing mesh).
grid::Multigrid<3, float>* hierarchy_or_skip(benchmark::State& state);

void evict_caches();

// Runs `kernel` once per iteration, evicting the caches first (untimed) in cold runs.
template <typename Kernel>
void run_kernel(benchmark::State& state, Kernel&& kernel) {
  const bool cold = state.range(2) == 1;
  for (auto _ : state) {
    if (cold) {
      state.PauseTiming();
      evict_caches();
      state.ResumeTiming();
    }
    kernel();
    benchmark::ClobberMemory();
  }
}

// A counter of the items (cells, rows) one kernel call handles, per second.
inline benchmark::Counter per_second(double items) {
  return benchmark::Counter(items, benchmark::Counter::kIsIterationInvariantRate);
}

// The finest level's active cells per second (every kernel reports it).
void count_active_cells(benchmark::State& state);

// The box at 16 (the smoke test), 64 and 128 cells, the armadillo at 48, 128 and 256, each warm
// (0) and cold (1). The armadillo at 48 fits the caches: a kernel's time per band row or
// lattice point there against 256 says how much of it is memory and how much its own
// instructions (the band sweeps: 55-75 % instructions, docs/notes/2026-12-08-band-cost-floor.md).
void kernel_cases(benchmark::internal::Benchmark* b);

}  // namespace mgelastic::bench
