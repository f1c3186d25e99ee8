#pragma once
// `mgelastic bench ...`: solver benchmarks printed as tables or JSON.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

namespace mgelastic::app {

struct BoxBenchOptions {
  int dim = 3;
  int n = 32;
  double poisson = 0.3;
  double youngs = 1e5;
  std::string bc = "mixed";
  int clamp_cells = 0;  // mixed box: Dirichlet slab thickness (grid::BoxSpec; 0 = n / 8)
  int cycles = 12;
  std::string precision = "double";
  double tolerance = 1e-6;
  int boundary_sweeps = 0;
  std::string cycle = "V";
  bool json = false;
  // bench vcycle --mesh: also the error history against the converged solution (error_history.hpp)
  bool error_history = false;
  int threads = 0;
  // bench cg: leave out the unpreconditioned CG (minutes at 128^3), keep hypre and multigrid.
  bool skip_cg = false;
  // bench vcycle: STREAM triad of this run (GB/s); > 0 adds the roofline to the record.
  double triad_gb_per_s = 0;
  // bench vcycle: MultigridOptions for studies of the rate (a negative value keeps the default;
  // band_layers: 1 for --mesh, the scenes' default, and 0 for the box).
  int band_layers = -1;
  // MultigridOptions::local_corrections (-1: the library's default).
  int local_corrections = -1;
  int relocation_sweeps = -1;
  std::string smoother_order = "auto";  // "block_local", "band_wide" (grid::BandSweepOrder)
  int max_levels = 0;
  int coarsest_min_cells = -1;
  double coarsest_max_boundary_fraction = -1;
  double refinement_reduction = -1;  // mixed precision (grid::MultigridOptions); 1: every cycle
  bool no_coarse_fill_weights = false;
  bool no_misaligned_clamp_depth = false;
  bool no_repair_coarse_cells = false;
  std::string coarse_dirichlet = "any_child";       // grid::CoarseDirichletRule
  std::string coarse_band_rows = "rediscretized";   // grid::CoarseBandRows
  std::string coarsest_operator = "rediscretized";  // grid::CoarsestOperator
  // bench vcycle: after the last cycle, the cubes of 8^3 cells holding most of the finest
  // residual (grid/residual_blocks.hpp), this many per run; 0 = none.
  int residual_blocks = 0;
};

void register_bench_commands(CLI::App& app);

// Runs the V-cycle convergence study on the box; returns the JSON record.
nlohmann::json run_convergence(const BoxBenchOptions& options);
// Runs the CG baseline on the non-augmented system of the same box.
nlohmann::json run_cg(const BoxBenchOptions& options);

}  // namespace mgelastic::app
