// The interior's distributive Gauss-Seidel (grid/distributive_smoother.hpp), one sweep over the
// finest level. Counter: lattice cells per second.
#include "grid/bench_hierarchy.hpp"
#include "mgelastic/grid/distributive_smoother.hpp"

namespace mgelastic::bench {
namespace {

void BM_DistributiveSweep(benchmark::State& state) {
  auto& level = mixed_box(static_cast<int>(state.range(0))).level(0);
  run_kernel(state, [&] { grid::distributive_sweep(level); });
  state.counters["cells/s"] = per_second(static_cast<double>(level.size()));
}
BENCHMARK(BM_DistributiveSweep)->Apply(box_sizes);

}  // namespace
}  // namespace mgelastic::bench
