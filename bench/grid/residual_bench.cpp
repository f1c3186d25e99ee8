// The residual of the finest level as the V-cycle evaluates it (grid/residual.hpp): its norm
// only (the convergence check after a cycle), band rows from the band-row planes the Multigrid
// keeps (grid/band_row_planes.hpp). Counter: active cells per second.
#include "grid/bench_hierarchy.hpp"
#include "mgelastic/grid/band_row_planes.hpp"
#include "mgelastic/grid/residual.hpp"

namespace mgelastic::bench {
namespace {

void BM_ResidualNorm(benchmark::State& state) {
  auto* found = hierarchy_or_skip(state);
  if (!found) return;
  const auto& level = found->level(0);
  const grid::BandRowPlanes planes = grid::band_row_planes(level);
  double norm = 0;
  run_kernel(state, [&] { norm = grid::fresh_residual_norm(level, &planes); });
  benchmark::DoNotOptimize(norm);
  count_active_cells(state);
}
BENCHMARK(BM_ResidualNorm)->Apply(kernel_cases);

}  // namespace
}  // namespace mgelastic::bench
