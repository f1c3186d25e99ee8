#pragma once
// What the grid kernel benchmarks run on: the paper's mixed box (Sec. 9.1; nu = 0.48, the lowest
// eighth clamped, float levels under a double solution level, the V-cycle's defaults) at the
// benchmark's argument in cells per axis, built once per process and cycled twice so every
// level holds a non-trivial right-hand side and correction.
//
// Cold runs: a kernel inside a V-cycle finds little of its data in cache (the passes between two
// calls stream the level's fields), so `cold` benchmarks evict the caches before each call
// (outside the timing) by writing a buffer twice the last-level cache.
#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <vector>

#include "mgelastic/grid/box_problem.hpp"
#include "mgelastic/grid/multigrid.hpp"

namespace mgelastic::bench {

struct BenchHierarchy {
  grid::ElasticityProblem<3> problem;
  std::unique_ptr<grid::Multigrid<3, float>> multigrid;
};

inline grid::Multigrid<3, float>& mixed_box(int cells) {
  static std::map<int, BenchHierarchy> built;
  BenchHierarchy& h = built[cells];
  if (!h.multigrid) {
    grid::BoxSpec spec;
    spec.cells = cells;
    spec.poisson_ratio = 0.48;
    h.problem = grid::make_box_problem<3>(spec);
    h.multigrid = std::make_unique<grid::Multigrid<3, float>>(h.problem, grid::MultigridOptions{});
    h.multigrid->run_cycles(2);
  }
  return *h.multigrid;
}

inline void evict_caches() {
  static std::vector<char> buffer(std::size_t(64) << 20);
  for (std::size_t i = 0; i < buffer.size(); i += 64) buffer[i] = static_cast<char>(buffer[i] + 1);
  benchmark::DoNotOptimize(buffer.data());
  benchmark::ClobberMemory();
}

// Runs `kernel` once per iteration, evicting the caches first (untimed) when the benchmark's
// second argument is 1.
template <typename Kernel>
void run_kernel(benchmark::State& state, Kernel&& kernel) {
  const bool cold = state.range(1) == 1;
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

// Sizes 16 (the smoke test), 64 and 128, each warm (0) and cold (1).
inline void box_sizes(benchmark::internal::Benchmark* b) {
  b->ArgNames({"cells", "cold"});
  for (int cells : {16, 64, 128})
    for (int cold : {0, 1}) b->Args({cells, cold});
  b->Unit(benchmark::kMillisecond)->UseRealTime();
}

}  // namespace mgelastic::bench
