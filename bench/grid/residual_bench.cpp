// The residual of the finest level as the V-cycle evaluates it (grid/residual.hpp): its norm
// only (the convergence check after a cycle), band rows from the band-row planes the Multigrid
// keeps (grid/band_row_planes.hpp). Counter: lattice cells per second.
#include "grid/bench_hierarchy.hpp"
#include "mgelastic/grid/band_row_planes.hpp"
#include "mgelastic/grid/residual.hpp"

namespace mgelastic::bench {
namespace {

void BM_ResidualNorm(benchmark::State& state) {
  const auto& level = mixed_box(static_cast<int>(state.range(0))).level(0);
  const grid::BandRowPlanes planes = grid::band_row_planes(level);
  double norm = 0;
  run_kernel(state, [&] { norm = grid::fresh_residual_norm(level, &planes); });
  benchmark::DoNotOptimize(norm);
  state.counters["cells/s"] = per_second(static_cast<double>(level.size()));
}
BENCHMARK(BM_ResidualNorm)->Apply(box_sizes);

}  // namespace
}  // namespace mgelastic::bench
