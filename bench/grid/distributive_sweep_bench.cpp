// The interior's distributive Gauss-Seidel (grid/distributive_smoother.hpp), one sweep over the
// finest level. Counter: active cells per second.
#include "grid/bench_hierarchy.hpp"
#include "mgelastic/grid/distributive_smoother.hpp"

namespace mgelastic::bench {
namespace {

void BM_DistributiveSweep(benchmark::State& state) {
  auto* found = hierarchy_or_skip(state);
  if (!found) return;
  auto& level = found->level(0);
  run_kernel(state, [&] { grid::distributive_sweep(level); });
  count_active_cells(state);
}
BENCHMARK(BM_DistributiveSweep)->Apply(kernel_cases);

}  // namespace
}  // namespace mgelastic::bench
