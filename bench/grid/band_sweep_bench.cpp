// The boundary band's Gauss-Seidel (grid/boundary_smoother.hpp) on the finest level: one call of
// the V-cycle's smoothing (its sweeps block by block, the rhs current), run-wise where the band
// forms runs (grid/band_runs.hpp). Counters: band row relaxations and
// active cells per second.
#include "grid/bench_hierarchy.hpp"
#include "mgelastic/grid/boundary_smoother.hpp"

namespace mgelastic::bench {
namespace {

void BM_BandSweeps(benchmark::State& state) {
  auto* found = hierarchy_or_skip(state);
  if (!found) return;
  auto& mg = *found;
  auto& level = mg.level(0);
  grid::refresh_band_rhs(level);
  const int sweeps = mg.boundary_sweeps();
  run_kernel(state, [&] {
    grid::band_gauss_seidel(level, sweeps, mg.options().band_sweep_order, grid::BandRhs::CURRENT);
  });
  const double relaxations = static_cast<double>(sweeps * level.band_kernel.rows());
  state.counters["row_relaxations/s"] = per_second(relaxations);
  state.counters["band_rows"] = static_cast<double>(level.band_kernel.rows());
  count_active_cells(state);
}
BENCHMARK(BM_BandSweeps)->Apply(kernel_cases);

}  // namespace
}  // namespace mgelastic::bench
