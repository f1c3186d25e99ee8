#include "grid/bench_hierarchy.hpp"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <utility>
#include <vector>

#include "mgelastic/core/error.hpp"
#include "mgelastic/grid/box_problem.hpp"
#include "mgelastic/scene/grid_setup.hpp"
#include "mgelastic/scene/mesh_benchmark_scene.hpp"

namespace mgelastic::bench {
namespace {

constexpr double kPoissonRatio = 0.48;

grid::ElasticityProblem<3> armadillo(int cells) {
  const char* data = std::getenv("MGELASTIC_DATA_DIR");
  if (!data || !*data) throw Error("MGELASTIC_DATA_DIR is not set (the armadillo's directory)");
  const std::string file = (std::filesystem::path(data) / "armadillo.obj").string();
  const nlohmann::json document = scene::mesh_benchmark_scene(file, cells, 1e5, kPoissonRatio);
  return scene::build_grid_setup(scene::parse_scene(document, "bench.json", ".")).problem;
}

void build(BenchHierarchy& h, int body, int cells) {
  grid::MultigridOptions options;
  if (body == 0) {
    grid::BoxSpec spec;
    spec.cells = cells;
    spec.poisson_ratio = kPoissonRatio;
    h.problem = grid::make_box_problem<3>(spec);
  } else {
    h.problem = armadillo(cells);
    options.band_layers = 1;  // the scenes' default
  }
  h.multigrid = std::make_unique<grid::Multigrid<3, float>>(h.problem, options);
  h.multigrid->run_cycles(2);
  const auto& level = h.multigrid->level(0);
  h.active_cells = static_cast<std::size_t>(
      std::count(level.cells.begin(), level.cells.end(), grid::CellType::INTERIOR));
}

}  // namespace

const BenchHierarchy& hierarchy(int body, int cells) {
  static std::map<std::pair<int, int>, BenchHierarchy> built;
  BenchHierarchy& h = built[{body, cells}];
  if (!h.multigrid && h.error.empty()) try {
      build(h, body, cells);
    } catch (const Error& e) {
      h.error = e.what();
    }
  return h;
}

grid::Multigrid<3, float>* hierarchy_or_skip(benchmark::State& state) {
  const BenchHierarchy& h =
      hierarchy(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  if (!h.multigrid) state.SkipWithError(h.error.c_str());
  return h.multigrid.get();
}

void evict_caches() {
  static std::vector<char> buffer(std::size_t(64) << 20);
  for (std::size_t i = 0; i < buffer.size(); i += 64) buffer[i] = static_cast<char>(buffer[i] + 1);
  benchmark::DoNotOptimize(buffer.data());
  benchmark::ClobberMemory();
}

void count_active_cells(benchmark::State& state) {
  const BenchHierarchy& h =
      hierarchy(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  state.counters["active_cells/s"] = per_second(static_cast<double>(h.active_cells));
}

void kernel_cases(benchmark::internal::Benchmark* b) {
  b->ArgNames({"body", "cells", "cold"});
  for (const auto& [body, cells] :
       {std::pair{0, 16}, {0, 64}, {0, 128}, {1, 48}, {1, 128}, {1, 256}})
    for (int cold : {0, 1}) b->Args({body, cells, cold});
  b->Unit(benchmark::kMillisecond)->UseRealTime();
}

}  // namespace mgelastic::bench
