// The V-cycle's transfers between the two finest float levels: the residual fused with its
// restriction (grid/residual_restriction.hpp, the step down) and the prolongation of the coarse
// correction added to the fine x (grid/transfer.hpp, the step up).
// Counter: fine active cells per second.
#include "grid/bench_hierarchy.hpp"
#include "mgelastic/grid/band_row_planes.hpp"
#include "mgelastic/grid/residual_restriction.hpp"
#include "mgelastic/grid/transfer.hpp"

namespace mgelastic::bench {
namespace {

void BM_ResidualRestriction(benchmark::State& state) {
  auto* found = hierarchy_or_skip(state);
  if (!found) return;
  auto& mg = *found;
  const auto& fine = mg.level(0);
  const grid::BandRowPlanes planes = grid::band_row_planes(fine);
  grid::ResidualWindows<float> windows;
  run_kernel(state, [&] { grid::restrict_fresh_residual(fine, planes, mg.level(1), windows); });
  count_active_cells(state);
}
BENCHMARK(BM_ResidualRestriction)->Apply(kernel_cases);

void BM_Prolongation(benchmark::State& state) {
  auto* found = hierarchy_or_skip(state);
  if (!found) return;
  auto& mg = *found;
  auto& fine = mg.level(0);
  run_kernel(state, [&] { grid::prolongate_correction(mg.level(1), fine); });
  count_active_cells(state);
}
BENCHMARK(BM_Prolongation)->Apply(kernel_cases);

}  // namespace
}  // namespace mgelastic::bench
