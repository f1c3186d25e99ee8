// The yardstick of the kernel benchmarks: STREAM triad (core/stream_triad.hpp) over three
// 64 MiB arrays with the current OpenMP thread count, run beside them so a kernel's bandwidth is
// read against this machine's in the same run. Counter: GB/s of the best repetition.
#include <benchmark/benchmark.h>

#include "mgelastic/core/stream_triad.hpp"

namespace mgelastic::bench {
namespace {

void BM_StreamTriad(benchmark::State& state) {
  double gb_per_s = 0;
  for (auto _ : state) gb_per_s = stream_triad_gb_per_s({.repetitions = 1});
  state.counters["GB_per_s"] = gb_per_s;
}
BENCHMARK(BM_StreamTriad)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace mgelastic::bench
