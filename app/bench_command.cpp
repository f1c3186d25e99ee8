#include "bench_command.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <exception>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include <omp.h>
#include <unistd.h>

#include "mgelastic/core/error.hpp"
#include "mgelastic/core/stream_triad.hpp"
#include "mgelastic/core/system_memory.hpp"
#include "mgelastic/core/threads.hpp"
#include "mgelastic/core/timer.hpp"
#include "mgelastic/grid/box_problem.hpp"
#include "mgelastic/grid/cg_baseline.hpp"
#include "mgelastic/grid/convergence_rate.hpp"
#include "mgelastic/grid/cycle_roofline.hpp"
#include "mgelastic/grid/disc_study.hpp"
#include "mgelastic/grid/error_history.hpp"
#include "mgelastic/grid/hypre_baseline.hpp"
#include "mgelastic/grid/layout_census.hpp"
#include "mgelastic/grid/multigrid.hpp"
#include "mgelastic/grid/nonaugmented_system.hpp"
#include "mgelastic/grid/residual_blocks.hpp"
#include "mgelastic/io/synthetic_lattice_frame.hpp"
#include "mgelastic/io/vtk_writers.hpp"
#include "mgelastic/scene/grid_setup.hpp"
#include "mgelastic/scene/mesh_benchmark_scene.hpp"
#include "mgelastic/scene/scene.hpp"
#include "mgelastic/tet/step_benchmark.hpp"
#include "mgelastic/validation/validation_suite.hpp"

namespace mgelastic::app {
namespace {

constexpr const char* kClampCellsHelp =
    "Thickness of the mixed box's Dirichlet slab in cells (default: n / 8); one that is not a "
    "multiple of 2^(levels - 1) puts the clamp between coarse faces";

// Cube edge (cells) of --residual-blocks: a few band widths, small next to a limb.
constexpr int kResidualBlockCells = 8;

grid::BoxSpec box_spec(const BoxBenchOptions& o) {
  grid::BoxSpec spec;
  spec.cells = o.n;
  spec.poisson_ratio = o.poisson;
  spec.youngs_modulus = o.youngs;
  spec.clamp_cells = o.clamp_cells;
  if (o.bc == "mixed") {
    spec.boundary = grid::BoxBoundary::MIXED;
  } else if (o.bc == "dirichlet") {
    spec.boundary = grid::BoxBoundary::DIRICHLET;
  } else {
    throw Error("must be 'mixed' or 'dirichlet' (got '" + o.bc + "')", {.pointer = "--bc"});
  }
  return spec;
}

// "float" (mixed: float cycles, solution and residuals in double), "single" (float only, the
// paper's setup) or "double"; true for the two with float levels.
bool float_levels(const BoxBenchOptions& o) {
  if (o.precision != "float" && o.precision != "single" && o.precision != "double")
    throw Error("must be 'float', 'single' or 'double' (got '" + o.precision + "')",
                {.pointer = "--precision"});
  return o.precision != "double";
}

// Relative residual below which cycles no longer count in the rate: round-off of the residual
// (double, or float in single precision) would pollute the ratios. The double residual of the
// 128^3 box stops at 3.5e-12 and its ratios climb from 1e-10 on, so 1e-9.
double rate_floor(const BoxBenchOptions& o) {
  return o.precision == "single" ? 1e-3 : 1e-9;
}

grid::MultigridOptions multigrid_options(const BoxBenchOptions& o) {
  grid::MultigridOptions options;
  options.boundary_sweeps = o.boundary_sweeps;
  options.mixed_precision = o.precision != "single";
  if (o.cycle == "V") {
    options.cycle = grid::CycleType::V;
  } else if (o.cycle == "W") {
    options.cycle = grid::CycleType::W;
  } else {
    throw Error("must be 'V' or 'W' (got '" + o.cycle + "')", {.pointer = "--cycle"});
  }
  if (o.band_layers >= 0) options.band_layers = o.band_layers;
  if (o.local_corrections >= 0) options.local_corrections = o.local_corrections;
  if (o.relocation_sweeps >= 0) options.relocation_sweeps = o.relocation_sweeps;
  if (o.refinement_reduction >= 0) options.refinement_reduction = o.refinement_reduction;
  options.band_sweep_order = grid::band_sweep_order(o.smoother_order);
  options.max_levels = o.max_levels;
  if (o.coarsest_min_cells >= 0) options.coarsest_min_cells = o.coarsest_min_cells;
  if (o.coarsest_max_boundary_fraction >= 0)
    options.coarsest_max_boundary_fraction = o.coarsest_max_boundary_fraction;
  options.coarse_fill_weights = !o.no_coarse_fill_weights;
  options.repair_coarse_cells = !o.no_repair_coarse_cells;
  options.misaligned_dirichlet_depth = !o.no_misaligned_clamp_depth;
  options.coarse_dirichlet = o.coarse_dirichlet == "every_child"
                                 ? grid::CoarseDirichletRule::EVERY_CHILD
                                 : grid::CoarseDirichletRule::ANY_CHILD;
  options.coarsest_operator = grid::coarsest_operator(o.coarsest_operator, "--coarsest-operator");
  options.coarse_band_rows = grid::coarse_band_rows(o.coarse_band_rows, "--coarse-band-rows");
  return options;
}

// The rows of the paper's Fig. 22 (and the cycle's own work), for the --json records.
nlohmann::json phase_seconds_json(const grid::PhaseSeconds& phases) {
  nlohmann::json json;
  for (int phase = 0; phase < grid::PhaseSeconds::count; ++phase)
    json[grid::PhaseSeconds::names[phase]] = phases[phase];
  return json;
}

nlohmann::json roofline_row_json(const grid::PhaseRoofline& row) {
  return {{"seconds", row.seconds},
          {"bytes", row.bytes},
          {"gb_per_s", row.gb_per_s},
          {"triad_fraction", row.triad_fraction}};
}

// Per cycle: each phase's seconds, model bytes, achieved GB/s and fraction of the triad.
template <int Dim, typename Scalar>
void add_roofline(nlohmann::json& record, const grid::Multigrid<Dim, Scalar>& mg,
                  const grid::SolveReport& report, double triad_gb_per_s) {
  if (triad_gb_per_s <= 0) return;
  const grid::CycleRoofline table = grid::cycle_roofline(mg, report, triad_gb_per_s);
  nlohmann::json phases;
  for (const auto& row : table.phases) phases[row.name] = roofline_row_json(row);
  record["triad_gb_per_s"] = table.triad_gb_per_s;
  record["roofline"] = {{"phases", phases},
                        {"cycle", roofline_row_json(table.total)},
                        {"unattributed_seconds", table.unattributed_seconds}};
}

// Where the working set goes: Multigrid::byte_breakdown in bytes per unknown, in its order.
template <int Dim, typename Scalar>
nlohmann::json memory_breakdown_json(const grid::Multigrid<Dim, Scalar>& mg) {
  nlohmann::json shares = nlohmann::json::array();
  const double unknowns = static_cast<double>(mg.unknowns());
  for (const grid::ByteShare& share : mg.byte_breakdown())
    shares.push_back({{"name", share.name},
                      {"bytes", share.bytes},
                      {"bytes_per_unknown", static_cast<double>(share.bytes) / unknowns}});
  return shares;
}

// Per active (interior) cell of the finest level: the record's time per V-cycle and working set,
// and the finest level's band momentum rows with the share of their relaxations done in runs
// (band_runs.hpp). Issue 24 compares embedded bodies with the box by these: a body's band is a
// larger fraction of its cells, and its rows form fewer runs.
template <int Dim, typename Scalar>
void add_per_cell_fields(nlohmann::json& record, const grid::Multigrid<Dim, Scalar>& mg) {
  const grid::Level<Dim, Scalar>& finest = mg.finest();
  const auto cells = static_cast<double>(
      std::count(finest.cells.begin(), finest.cells.end(), grid::CellType::INTERIOR));
  const auto& runs = finest.band_runs;
  record["active_cells"] = cells;
  record["ns_per_active_cell"] = record["vcycle_seconds"].get<double>() / cells * 1e9;
  record["bytes_per_active_cell"] = record["working_set_bytes"].get<double>() / cells;
  record["band_rows_per_active_cell"] = static_cast<double>(finest.band_kernel.rows()) / cells;
  // Lattice points per active cell that each layout would keep, over all levels (issue 24's
  // tiles, measured before they are built; grid/layout_census.hpp).
  std::vector<const grid::Level<Dim, Scalar>*> levels;
  for (int l = 0; l < mg.levels(); ++l) levels.push_back(&mg.level(l));
  const grid::LayoutCensus census = grid::layout_census(levels, {{4, 4, 4}, {8, 8, 8}, {32, 8, 4}});
  nlohmann::json layout = {{"bounding_box", census.bounding_box / cells},
                           {"with_variables", census.with_variables / cells},
                           {"live_pages", census.live_pages / cells},
                           {"row_ranges", census.row_ranges / cells}};
  for (const grid::TileCensus& tiles : census.tiles)
    layout["tiles_" + std::to_string(tiles.size[0]) + "x" + std::to_string(tiles.size[1]) + "x" +
           std::to_string(tiles.size[2])] = tiles.points / cells;
  record["layout_points_per_active_cell"] = layout;
  record["band_relaxations_in_runs"] = runs.row_relaxations > 0
                                           ? static_cast<double>(runs.row_relaxations_in_runs) /
                                                 static_cast<double>(runs.row_relaxations)
                                           : 0.0;
}

// Where the finest residual sits after the last cycle (the double level: not in single
// precision, which has none).
template <int Dim, typename Scalar>
void add_residual_blocks(nlohmann::json& record, const grid::Multigrid<Dim, Scalar>& mg,
                         int count) {
  if (count <= 0 || mg.single_precision()) return;
  nlohmann::json blocks = nlohmann::json::array();
  for (const auto& block : grid::residual_blocks<Dim>(mg.solution_level(), kResidualBlockCells,
                                                      static_cast<std::size_t>(count)))
    blocks.push_back({{"first_cell", block.first}, {"share", block.share}});
  record["residual_blocks"] = blocks;
  const auto shares = grid::residual_shares<Dim>(mg.solution_level());
  record["residual_shares"] = {{"field", shares.field},
                               {"next_to_dirichlet", shares.next_to_dirichlet},
                               {"next_to_exterior", shares.next_to_exterior},
                               {"elsewhere", shares.elsewhere}};
}

// The fields every V-cycle record shares: seconds per cycle, memory, phases and roofline.
template <int Dim, typename Scalar>
void add_cycle_fields(nlohmann::json& record, const grid::Multigrid<Dim, Scalar>& mg,
                      const grid::SolveReport& report, double triad_gb_per_s) {
  record["vcycle_seconds"] = report.seconds / std::max(1, report.cycles());
  record["working_set_bytes"] = mg.bytes();
  add_per_cell_fields(record, mg);
  record["memory_breakdown"] = memory_breakdown_json(mg);
  record["threads"] = thread_count();
  record["peak_rss_bytes"] = peak_resident_bytes();
  record["phase_seconds"] = phase_seconds_json(mg.phase_seconds());
  // Mixed precision: cycles that added the correction in double, and float residual norms.
  record["refinements"] = mg.refinements();
  record["float_norms"] = mg.float_norms();
  nlohmann::json boxes = nlohmann::json::array();
  for (int i = 0; i < mg.local_corrections(); ++i) {
    const auto& local = mg.local_correction(i);
    std::vector<int> lo(Dim), hi(Dim);
    for (int a = 0; a < Dim; ++a) {
      lo[a] = local.lo()[a];
      hi[a] = local.hi()[a];
    }
    boxes.push_back({{"lo", lo}, {"hi", hi}, {"unknowns", local.unknowns()}});
  }
  record["local_corrections"] = boxes;
  add_roofline(record, mg, report, triad_gb_per_s);
}

template <int Dim, typename Scalar>
nlohmann::json convergence(const BoxBenchOptions& o) {
  grid::MultigridOptions options = multigrid_options(o);
  const grid::ElasticityProblem<Dim> problem = grid::make_box_problem<Dim>(box_spec(o));
  const Timer setup;
  grid::Multigrid<Dim, Scalar> mg(problem, options);
  const double setup_seconds = setup.seconds();
  const grid::SolveReport report = mg.run_cycles(o.cycles);
  // Residuals are evaluated in double except in single precision, whose float round-off ends
  // the reduction near 1e-4 relative on the box (the rate counts cycles above 1e-3).
  const double floor = rate_floor(o);
  nlohmann::json record = {
      {"benchmark", "convergence"},
      {"dim", Dim},
      {"n", o.n},
      {"poisson", o.poisson},
      {"bc", o.bc},
      {"precision", o.precision},
      {"cycle", o.cycle},
      {"boundary_sweeps", mg.boundary_sweeps()},
      {"levels", mg.levels()},
      {"unknowns", mg.unknowns()},
      {"residuals", report.residuals},
      {"relative_residual", report.residuals.back() / report.residuals.front()},
      {"rate", grid::convergence_rate(report.residuals, floor)},
      {"last_ratio", grid::last_ratio(report.residuals, floor)},
      {"rate_settled", grid::rate_settled(report.residuals, floor)},
      {"solve_seconds", report.seconds},
      {"setup_seconds", setup_seconds},
      {"coarse_band_rows", o.coarse_band_rows}};
  if (o.bc == "mixed") record["clamp_cells"] = grid::clamp_thickness(box_spec(o));
  add_cycle_fields(record, mg, report, o.triad_gb_per_s);
  add_residual_blocks(record, mg, o.residual_blocks);
  return record;
}

// CPU time of the whole process (all threads), seconds.
double process_cpu_seconds() {
  return static_cast<double>(std::clock()) / CLOCKS_PER_SEC;
}

template <int Dim, typename Scalar>
nlohmann::json cg(const BoxBenchOptions& o) {
  // The level's classification and Dirichlet values give the same discrete problem as the
  // multigrid solver sees; only the finest level is needed. The whole hierarchy is built (cheap)
  // because capping the levels would factorize a large coarsest level directly (at 128^3 a
  // 64^3 sparse factorization: many minutes and gigabytes).
  const auto problem = grid::make_box_problem<Dim>(box_spec(o));
  grid::Multigrid<Dim, double> mg(problem, grid::MultigridOptions{});
  const auto system = grid::assemble_nonaugmented(mg.finest(), problem.boundary_stress);
  const Eigen::SparseMatrix<double, Eigen::RowMajor> a = system.matrix;
  const Eigen::VectorXd rhs = system.right_hand_side(mg.finest());
  Eigen::VectorXd u = Eigen::VectorXd::Zero(rhs.size());
  // Process CPU seconds next to the wall seconds: on a loaded machine the wall time of each
  // solver depends on the others' load, its CPU time much less.
  double cpu = process_cpu_seconds();
  grid::CgReport report;
  if (!o.skip_cg) report = grid::conjugate_gradient(a, rhs, u, o.tolerance, 100000);
  const double cg_cpu = process_cpu_seconds() - cpu;
  // The multigrid solver on the same problem and tolerance, side by side in the same run.
  grid::Multigrid<Dim, Scalar> solver(problem, multigrid_options(o));
  cpu = process_cpu_seconds();
  const grid::SolveReport mg_report = solver.solve(o.tolerance, 200);
  const double mg_cpu = process_cpu_seconds() - cpu;
  // hypre BoomerAMG-PCG on the same matrix (when configured with hypre).
  std::vector<int> component(system.u_variables.size());
  for (std::size_t i = 0; i < component.size(); ++i)
    component[i] = static_cast<int>(system.u_variables[i] / mg.finest().size());
  Eigen::VectorXd hypre_u;
  cpu = process_cpu_seconds();
  const grid::HypreReport hypre =
      grid::boomeramg_pcg(a, rhs, component, Dim, o.tolerance, 2000, hypre_u);
  const double hypre_cpu = process_cpu_seconds() - cpu;
  return {{"benchmark", "cg"},
          {"hypre_available", hypre.available},
          {"hypre_iterations", hypre.iterations},
          {"hypre_setup_seconds", hypre.setup_seconds},
          {"hypre_solve_seconds", hypre.solve_seconds},
          {"hypre_converged", hypre.converged},
          {"hypre_cpu_seconds", hypre_cpu},
          {"multigrid_cycles", mg_report.cycles()},
          {"multigrid_seconds", mg_report.seconds},
          {"multigrid_cpu_seconds", mg_cpu},
          {"multigrid_converged", mg_report.converged},
          {"multigrid_precision", o.precision},
          {"dim", Dim},
          {"n", o.n},
          {"poisson", o.poisson},
          {"bc", o.bc},
          {"unknowns", rhs.size()},
          {"tolerance", o.tolerance},
          {"iterations", report.iterations},
          {"converged", report.converged},
          {"seconds", report.seconds},
          {"cpu_seconds", cg_cpu},
          {"cg_skipped", o.skip_cg},
          {"residuals", report.residuals}};
}

void print_convergence(const nlohmann::json& r) {
  std::printf("mixed-formulation multigrid (%s(1,1) cycles), %dD box N=%d, nu=%.4g, bc=%s, %s\n",
              r["cycle"].get<std::string>().c_str(), r["dim"].get<int>(), r["n"].get<int>(),
              r["poisson"].get<double>(), r["bc"].get<std::string>().c_str(),
              r["precision"].get<std::string>().c_str());
  std::printf("levels %d, interior unknowns %zu, boundary sweeps %d\n", r["levels"].get<int>(),
              r["unknowns"].get<std::size_t>(), r["boundary_sweeps"].get<int>());
  std::printf("%6s %14s %8s\n", "cycle", "residual", "ratio");
  const auto res = r["residuals"].get<std::vector<double>>();
  for (std::size_t k = 0; k < res.size(); ++k) {
    if (k == 0) {
      std::printf("%6zu %14.6e %8s\n", k, res[k], "");
    } else {
      std::printf("%6zu %14.6e %8.4f\n", k, res[k], res[k] / res[k - 1]);
    }
  }
  std::printf("rate %.4f, relative residual %.3e, %.4f s per V-cycle\n", r["rate"].get<double>(),
              r["relative_residual"].get<double>(), r["vcycle_seconds"].get<double>());
}

void print_cg(const nlohmann::json& r) {
  std::printf("CG on the non-augmented system, %dD box N=%d, nu=%.4g, bc=%s, %zu unknowns\n",
              r["dim"].get<int>(), r["n"].get<int>(), r["poisson"].get<double>(),
              r["bc"].get<std::string>().c_str(), r["unknowns"].get<std::size_t>());
  if (r["cg_skipped"].get<bool>()) {
    std::printf("CG:        skipped (--skip-cg)\n");
  } else {
    std::printf("CG:        %5d iterations to relative residual %.1e (%s), %.3f s (%.3f s CPU)\n",
                r["iterations"].get<int>(), r["tolerance"].get<double>(),
                r["converged"].get<bool>() ? "converged" : "NOT converged",
                r["seconds"].get<double>(), r["cpu_seconds"].get<double>());
  }
  if (r["hypre_available"].get<bool>()) {
    std::printf(
        "hypre:     %5d BoomerAMG-PCG iterations (%s), %.3f s setup + %.3f s solve (%.3f s CPU)\n",
        r["hypre_iterations"].get<int>(),
        r["hypre_converged"].get<bool>() ? "converged" : "NOT converged",
        r["hypre_setup_seconds"].get<double>(), r["hypre_solve_seconds"].get<double>(),
        r["hypre_cpu_seconds"].get<double>());
  }
  std::printf("multigrid: %5d V(1,1) cycles (%s) to the same tolerance (%s), %.3f s (%.3f s CPU)\n",
              r["multigrid_cycles"].get<int>(), r["multigrid_precision"].get<std::string>().c_str(),
              r["multigrid_converged"].get<bool>() ? "converged" : "NOT converged",
              r["multigrid_seconds"].get<double>(), r["multigrid_cpu_seconds"].get<double>());
}

void add_box_options(CLI::App* cmd, BoxBenchOptions& o) {
  cmd->add_option("--dim", o.dim, "Dimension (2 or 3)")->check(CLI::IsMember({2, 3}));
  cmd->add_option("--n", o.n, "Cells per axis of the box");
  cmd->add_option("--poisson", o.poisson, "Poisson ratio in [0, 0.5)");
  cmd->add_option("--youngs", o.youngs, "Young's modulus (Pa)");
  cmd->add_option("--bc", o.bc, "Boundary conditions: mixed or dirichlet");
  cmd->add_option("--clamp-cells", o.clamp_cells, kClampCellsHelp);
  cmd->add_flag("--json", o.json, "Print JSON instead of a table");
  cmd->add_option("--cycle", o.cycle, "Multigrid cycle: V (Algorithm 1, default) or W");
  cmd->add_option("--threads", o.threads, "Worker threads (default: all cores)");
}

}  // namespace

nlohmann::json run_convergence(const BoxBenchOptions& o) {
  const bool single = float_levels(o);
  if (o.cycles < 1)
    throw Error("must be at least 1 (got " + std::to_string(o.cycles) + ")",
                {.pointer = "--cycles"});
  if (o.dim == 2) return single ? convergence<2, float>(o) : convergence<2, double>(o);
  return single ? convergence<3, float>(o) : convergence<3, double>(o);
}

nlohmann::json run_cg(const BoxBenchOptions& o) {
  const bool single = float_levels(o);
  if (o.dim == 2) return single ? cg<2, float>(o) : cg<2, double>(o);
  return single ? cg<3, float>(o) : cg<3, double>(o);
}

void run_disc_accuracy(bool json) {
  nlohmann::json records = nlohmann::json::array();
  for (double nu : {0.2, 0.49}) {
    const grid::DiscStudy study = grid::run_disc_study(nu, {16, 32, 64, 128, 256, 512});
    nlohmann::json rows = nlohmann::json::array();
    if (!json)
      std::printf("nu = %.2f\n%8s %12s %10s %8s %8s\n", nu, "cells", "max error", "unknowns",
                  "cycles", "rate");
    for (const auto& r : study.rows) {
      rows.push_back({{"cells", r.cells},
                      {"max_error", r.max_error},
                      {"unknowns", r.unknowns},
                      {"cycles", r.cycles},
                      {"rate", r.rate}});
      if (!json)
        std::printf("%8d %12.4e %10zu %8d %8.3f\n", r.cells, r.max_error, r.unknowns, r.cycles,
                    r.rate);
    }
    if (!json) std::printf("observed order (two finest): %.3f\n\n", study.order);
    records.push_back({{"poisson", nu}, {"rows", rows}, {"order", study.order}});
  }
  if (json)
    std::cout << nlohmann::json{{"benchmark", "disc-accuracy"}, {"studies", records}}.dump(2)
              << "\n";
}

// The paper's armadillo-style run (Fig. 22): a surface mesh voxelized at `resolution` cells
// along its longest axis (one padding layer, the scenes' extra band layer), its lowest 5 % of
// height fixed, under gravity; float V(1,1) cycles. Same record as run_convergence.
nlohmann::json mesh_vcycle(const std::string& file, int resolution, const BoxBenchOptions& o) {
  if (resolution < 8)
    throw Error("must be at least 8 (got " + std::to_string(resolution) + ")",
                {.pointer = "--resolution"});
  const nlohmann::json document =
      scene::mesh_benchmark_scene(file, resolution, o.youngs, o.poisson);
  const Timer scene_timer;  // voxelization, cell types, loads: what precedes the solver's setup
  const scene::GridSetup setup =
      scene::build_grid_setup(scene::parse_scene(document, "bench.json", "."));
  const double scene_seconds = scene_timer.seconds();
  grid::MultigridOptions options = multigrid_options(o);
  if (o.band_layers < 0) options.band_layers = 1;              // the scenes' default
  if (o.local_corrections < 0) options.local_corrections = 4;  // the scenes' default
  const Timer setup_timer;
  grid::Multigrid<3, float> mg(setup.problem, options);
  const double setup_seconds = setup_timer.seconds();
  // Process CPU seconds too: rates and CPU time per cycle do not depend on the machine's load.
  const double cpu = process_cpu_seconds();
  const grid::SolveReport report = mg.run_cycles(o.cycles);
  const double cycle_cpu = (process_cpu_seconds() - cpu) / std::max(1, report.cycles());
  const double floor = rate_floor(o);
  nlohmann::json record = {{"benchmark", "convergence"},
                           {"mesh", file},
                           {"dim", 3},
                           {"n", resolution},
                           {"interior_cells", setup.interior_cells},
                           {"poisson", o.poisson},
                           {"precision", o.precision == "single" ? "single" : "float"},
                           {"cycle", o.cycle},
                           {"boundary_sweeps", mg.boundary_sweeps()},
                           {"levels", mg.levels()},
                           {"unknowns", mg.unknowns()},
                           {"residuals", report.residuals},
                           {"rate", grid::convergence_rate(report.residuals, floor)},
                           {"last_ratio", grid::last_ratio(report.residuals, floor)},
                           {"rate_settled", grid::rate_settled(report.residuals, floor)},
                           {"setup_seconds", setup_seconds},
                           {"scene_seconds", scene_seconds}};
  add_cycle_fields(record, mg, report, o.triad_gb_per_s);
  add_residual_blocks(record, mg, o.residual_blocks);
  record["vcycle_cpu_seconds"] = cycle_cpu;
  if (o.error_history) {
    const grid::ErrorHistory history =
        grid::error_history<3, float>(setup.problem, options, o.cycles);
    record["error_history"] = history.relative_error;
    record["error_rate"] = grid::convergence_rate(history.relative_error, 1e-8);
    record["reference_relative_residual"] = history.reference_residual;
  }
  return record;
}

// One run's roofline: per V-cycle, seconds, model bytes, achieved GB/s, fraction of triad.
void print_roofline(const nlohmann::json& r, const BoxBenchOptions& base) {
  if (r.contains("mesh")) {
    std::printf("mesh %s at %d, %d thread(s)", r["mesh"].get<std::string>().c_str(),
                r["n"].get<int>(), r["threads"].get<int>());
  } else {
    std::printf("%d^3 mixed box, %d thread(s)", r["n"].get<int>(), r["threads"].get<int>());
  }
  std::printf(", %s, %d cycles: triad %.2f GB/s\n", base.precision.c_str(),
              static_cast<int>(r["residuals"].size()) - 1, r["triad_gb_per_s"].get<double>());
  std::printf("%-20s %10s %10s %8s %8s\n", "phase", "s/cycle", "MB/cycle", "GB/s", "triad");
  const auto row = [](const std::string& name, const nlohmann::json& p) {
    std::printf("%-20s %10.4f %10.1f %8.2f %7.0f%%\n", name.c_str(), p["seconds"].get<double>(),
                p["bytes"].get<double>() / 1e6, p["gb_per_s"].get<double>(),
                100 * p["triad_fraction"].get<double>());
  };
  for (const char* phase : grid::PhaseSeconds::names) row(phase, r["roofline"]["phases"][phase]);
  const double unattributed = r["roofline"]["unattributed_seconds"].get<double>();
  const double cycle = r["roofline"]["cycle"]["seconds"].get<double>();
  std::printf("%-20s %10.4f %10s %8s %8s  (%.1f%% of the cycle)\n", "unattributed", unattributed,
              "", "", "", cycle > 0 ? 100 * unattributed / cycle : 0.0);
  row("total per V-cycle", r["roofline"]["cycle"]);
  std::printf("\n");
}

// Rate, working set and levels of every run side by side.
void print_profile_summary(const nlohmann::json& records, const BoxBenchOptions& base) {
  std::printf("V(1,1) profile, 3D mixed box, nu=%.3g, %s, %d cycles\n", base.poisson,
              base.precision.c_str(), base.cycles);
  std::printf("%-20s", "run");
  for (const auto& r : records) {
    if (r.contains("mesh")) {
      std::printf(" | mesh %3d %dT", r["n"].get<int>(), r["threads"].get<int>());
    } else {
      std::printf(" | %4d^3 %dT", r["n"].get<int>(), r["threads"].get<int>());
    }
  }
  std::printf("\n%-20s", "total per V-cycle");
  for (const auto& r : records) std::printf(" | %9.4f", r["vcycle_seconds"].get<double>());
  if (std::any_of(records.begin(), records.end(),
                  [](const auto& r) { return r.contains("vcycle_cpu_seconds"); })) {
    std::printf("\n%-20s", "CPU s per V-cycle");
    for (const auto& r : records)
      r.contains("vcycle_cpu_seconds")
          ? (void)std::printf(" | %9.4f", r["vcycle_cpu_seconds"].get<double>())
          : (void)std::printf(" | %9s", "-");
  }
  std::printf("\n%-20s", "rate");
  for (const auto& r : records) std::printf(" | %9.3f", r["rate"].get<double>());
  // The last ratio, starred while the ratios still climb: then the rate is a lower bound of the
  // asymptotic one (convergence_rate.hpp; run more --cycles).
  std::printf("\n%-20s", "last ratio");
  for (const auto& r : records)
    std::printf(" | %8.3f%s", r["last_ratio"].get<double>(),
                r["rate_settled"].get<bool>() ? " " : "*");
  if (std::any_of(records.begin(), records.end(),
                  [](const auto& r) { return r.contains("error_history"); })) {
    // Relative error against the converged solution: first cycle's ratio and the rate.
    std::printf("\n%-20s", "error, cycle 1");
    for (const auto& r : records)
      r.contains("error_history")
          ? (void)std::printf(" | %9.3f", r["error_history"][1].get<double>())
          : (void)std::printf(" | %9s", "-");
    std::printf("\n%-20s", "error rate");
    for (const auto& r : records)
      r.contains("error_rate") ? (void)std::printf(" | %9.3f", r["error_rate"].get<double>())
                               : (void)std::printf(" | %9s", "-");
  }
  std::printf("\n%-20s", "working set (MB)");
  for (const auto& r : records) std::printf(" | %9.1f", r["working_set_bytes"].get<double>() / 1e6);
  std::printf("\n%-20s", "peak RSS (MB)");
  for (const auto& r : records) std::printf(" | %9.1f", r["peak_rss_bytes"].get<double>() / 1e6);
  std::printf("\n%-20s", "solver setup (s)");
  for (const auto& r : records) std::printf(" | %9.2f", r["setup_seconds"].get<double>());
  if (std::any_of(records.begin(), records.end(),
                  [](const nlohmann::json& r) { return r.contains("scene_seconds"); })) {
    std::printf("\n%-20s", "scene, voxels (s)");
    for (const auto& r : records)
      r.contains("scene_seconds") ? (void)std::printf(" | %9.2f", r["scene_seconds"].get<double>())
                                  : (void)std::printf(" | %9s", "-");
  }
  std::printf("\n%-20s", "levels");
  for (const auto& r : records) std::printf(" | %9d", r["levels"].get<int>());
  std::printf("\n%-20s", "bytes per unknown");
  for (const auto& r : records)
    std::printf(" | %9.0f", r["working_set_bytes"].get<double>() / r["unknowns"].get<double>());
  const std::vector<std::pair<const char*, const char*>> per_cell = {
      {"active cells", "active_cells"},
      {"ns/cycle per cell", "ns_per_active_cell"},
      {"bytes per cell", "bytes_per_active_cell"},
      {"band rows per cell", "band_rows_per_active_cell"},
      {"band in runs", "band_relaxations_in_runs"}};
  for (const auto& [label, key] : per_cell) {
    std::printf("\n%-20s", label);
    for (const auto& r : records) {
      const double value = r[key].get<double>();
      std::printf(value >= 100 ? " | %9.0f" : " | %9.3f", value);
    }
  }
  // Lattice points per active cell, all levels: today's box, the floor, and the tiled layouts.
  const std::vector<std::pair<const char*, const char*>> layouts = {
      {"points/cell: box", "bounding_box"}, {"  with a variable", "with_variables"},
      {"  4 KiB pages", "live_pages"},      {"  x-range per row", "row_ranges"},
      {"  4^3 tiles", "tiles_4x4x4"},       {"  8^3 tiles", "tiles_8x8x8"},
      {"  32x8x4 tiles", "tiles_32x8x4"}};
  for (const auto& [label, key] : layouts) {
    std::printf("\n%-20s", label);
    for (const auto& r : records)
      std::printf(" | %9.2f", r["layout_points_per_active_cell"][key].get<double>());
  }
  std::printf("\n");
  // The breakdown rows (the same groups in every run of one precision).
  std::printf("%-36s", "bytes per unknown by array group");
  for (const auto& r : records)
    std::printf(" | %9.0f", r["working_set_bytes"].get<double>() / r["unknowns"].get<double>());
  std::printf("\n");
  const nlohmann::json& groups = records.front()["memory_breakdown"];
  for (std::size_t g = 0; g < groups.size(); ++g) {
    std::printf("  %-34s", groups[g]["name"].get<std::string>().c_str());
    for (const auto& r : records)
      std::printf(" | %9.2f", r["memory_breakdown"][g]["bytes_per_unknown"].get<double>());
    std::printf("\n");
  }
  for (const auto& r : records)
    if (r.contains("mesh"))
      std::printf("mesh %s: %zu interior cells at resolution %d\n",
                  r["mesh"].get<std::string>().c_str(), r["interior_cells"].get<std::size_t>(),
                  r["n"].get<int>());
  for (const auto& r : records) {
    if (!r.contains("residual_blocks")) continue;
    const std::string run =
        r.contains("mesh") ? std::filesystem::path(r["mesh"].get<std::string>()).stem().string() +
                                 " at " + std::to_string(r["n"].get<int>())
                           : std::to_string(r["n"].get<int>()) + "^3 box";
    std::printf(
        "%s: residual after the last cycle, largest shares by %d^3-cell cube (first "
        "cell):",
        run.c_str(), kResidualBlockCells);
    for (const auto& b : r["residual_blocks"])
      std::printf(" (%d,%d,%d) %.3f", b["first_cell"][0].get<int>(), b["first_cell"][1].get<int>(),
                  b["first_cell"][2].get<int>(), b["share"].get<double>());
    std::printf("\n");
    const auto& s = r["residual_shares"];
    std::printf(
        "%s: by field u_x %.3f u_y %.3f u_z %.3f p %.3f; next to a Dirichlet cell %.3f, next to "
        "the exterior %.3f, elsewhere %.3f\n",
        run.c_str(), s["field"][0].get<double>(), s["field"][1].get<double>(),
        s["field"][2].get<double>(), s["field"][3].get<double>(),
        s["next_to_dirichlet"].get<double>(), s["next_to_exterior"].get<double>(),
        s["elsewhere"].get<double>());
  }
  if (std::any_of(records.begin(), records.end(),
                  [](const auto& r) { return !r.value("rate_settled", true); }))
    std::printf(
        "* the last three ratios differ by more than 0.01: the rate is a lower bound of the "
        "asymptotic one (embedded bodies need 20-30 --cycles)\n");
}

// Fig. 22/23-style profile: seconds per subroutine and per V-cycle on the mixed box (and on
// surface meshes, `meshes`, voxelized at `resolution`).
void run_vcycle_profile(const std::vector<int>& sizes, const std::vector<int>& threads,
                        const BoxBenchOptions& base, const std::vector<std::string>& meshes = {},
                        int resolution = 0) {
  nlohmann::json records = nlohmann::json::array();
  for (int t : threads) {
    set_thread_count(t);
    // The roofline's ceiling, measured with this thread count in this run.
    BoxBenchOptions o = base;
    o.triad_gb_per_s = stream_triad_gb_per_s();
    for (int n : sizes) {
      o.n = n;
      records.push_back(run_convergence(o));
    }
    for (const std::string& file : meshes) records.push_back(mesh_vcycle(file, resolution, o));
  }
  set_thread_count(0);
  if (base.json) {
    std::cout << nlohmann::json{{"benchmark", "vcycle"}, {"runs", records}}.dump(2) << "\n";
    return;
  }
  for (const auto& r : records) print_roofline(r, base);
  print_profile_summary(records, base);
}

// Georgii & Westermann Table 1/2 (tet/step_benchmark.hpp); milliseconds per step.
struct TetStepOptions {
  std::vector<int> cells{8, 11, 14};
  std::vector<std::string> meshes;
  int refine = 0, steps = 5, threads = 0, coarsest = 300, vcycles = 1, adaptive_patches = 0;
  double tolerance = 1e-6, cell_factor = 1.587;
  std::string rotation = "energy";
  std::string patches;  // "VALENCE[,SIZE]": feature patches (tet/feature_patches.hpp)
  bool symmetric = false, json = false, hypre = false, lexicographic = false, steps_only = false;
};

// "--patches VALENCE[,SIZE]": max valence >= 1, patch size >= 1 (12 when not given).
tet::FeaturePatchSettings parse_feature_patches(const std::string& text) {
  tet::FeaturePatchSettings settings;
  if (text.empty()) return settings;
  const auto bad = [&](const std::string& why) -> Error {
    return Error(why + " (got '" + text + "')", {.pointer = "--patches"});
  };
  const std::size_t comma = text.find(',');
  const auto positive = [&](const std::string& field, const char* name) {
    std::size_t used = 0;
    int value = 0;
    try {
      value = std::stoi(field, &used);
    } catch (const std::exception&) {
      throw bad(std::string("expected VALENCE[,SIZE] as integers: ") + name + " is not one");
    }
    if (used != field.size())
      throw bad(std::string("expected VALENCE[,SIZE] as integers: ") + name + " is not one");
    if (value < 1) throw bad(std::string(name) + " must be at least 1");
    return value;
  };
  settings.max_valence = positive(text.substr(0, comma), "VALENCE");
  if (comma != std::string::npos) settings.max_size = positive(text.substr(comma + 1), "SIZE");
  return settings;
}

// hypre BoomerAMG-PCG (grid/hypre_baseline.hpp) on a tet step matrix (unknowns vertex-major).
tet::ExternalSolveResult tet_boomeramg(const Eigen::SparseMatrix<double, Eigen::RowMajor>& a,
                                       const Eigen::VectorXd& b, double tolerance) {
  std::vector<int> component(b.size());
  for (Eigen::Index i = 0; i < b.size(); ++i) component[i] = static_cast<int>(i % 3);
  Eigen::VectorXd x;
  const grid::HypreReport report = grid::boomeramg_pcg(a, b, component, 3, tolerance, 2000, x);
  return {report.available, report.iterations, report.setup_seconds, report.solve_seconds,
          report.converged};
}

void run_tet_step(const TetStepOptions& o) {
  for (const int n : o.cells)
    if (n < 2)
      throw Error("must be at least 2 (got " + std::to_string(n) + ")", {.pointer = "--cells"});
  if (o.steps < 1)
    throw Error("must be at least 1 (got " + std::to_string(o.steps) + ")", {.pointer = "--steps"});
  if (!(o.tolerance > 0.0)) throw Error("must be positive", {.pointer = "--tolerance"});
  if (o.coarsest < 1) throw Error("must be at least 1", {.pointer = "--coarsest"});
  if (o.vcycles < 1) throw Error("must be at least 1", {.pointer = "--vcycles"});
  tet::TetStepBenchmarkOptions base;
  base.steps = o.steps;
  base.vcycles = o.vcycles;
  base.tolerance = o.tolerance;
  base.refinements = o.refine;
  base.multigrid.hierarchy.max_coarsest_vertices = o.coarsest;
  base.multigrid.hierarchy.first_cell_factor = o.cell_factor;
  base.multigrid.symmetric_sweeps = o.symmetric;
  base.multigrid.lexicographic = o.lexicographic;
  base.multigrid.patches = parse_feature_patches(o.patches);
  base.multigrid.adaptive_patches.rounds = o.adaptive_patches;
  base.steps_only = o.steps_only;
  if (o.hypre) base.external_solver = tet_boomeramg;
  base.rotation = o.rotation == "polar"            ? tet::RotationMethod::POLAR
                  : o.rotation == "smoothed_polar" ? tet::RotationMethod::POLAR_SMOOTHED
                                                   : tet::RotationMethod::ENERGY_MINIMIZATION;
  std::vector<tet::TetStepBenchmarkOptions> runs;
  for (const int n : o.cells) {
    runs.push_back(base);
    runs.back().cells_across = n;
  }
  for (const std::string& file : o.meshes) {
    runs.push_back(base);
    runs.back().mesh_file = file;
  }
  nlohmann::json rows = nlohmann::json::array();
  if (!o.json)
    std::printf(
        "%7s %6s %11s | %6s %6s | %6s %6s | %5s %5s %6s | %6s %6s %6s | %6s %6s | %5s %8s | %9s "
        "%9s %9s | %14s | %9s | %5s\n",
        "tets", "verts", "coarsest", "rotate", "assem", "naive", "stream", "A0", "chol", "solve",
        "step", "cpu", "steps/s", "BJ st/s", "MB", "rate", "step res", "BJ-PCG", "MG-PCG",
        "V to tol", "AMG-PCG set+sol", "patches", "setup");
  for (const tet::TetStepBenchmarkOptions& run : runs) {
    const tet::TetStepBenchmark r = tet::run_tet_step_benchmark(run);
    rows.push_back({{"mesh", r.mesh},
                    {"tets", r.tets},
                    {"vertices", r.vertices},
                    {"levels", r.levels},
                    {"level_vertices", r.level_vertices},
                    {"threads", r.threads},
                    {"rotation", o.rotation},
                    {"vcycles", o.vcycles},
                    {"symmetric_sweeps", o.symmetric},
                    {"setup_seconds", r.setup_seconds},
                    {"rotate_seconds", r.rotate_seconds},
                    {"assemble_seconds", r.assemble_seconds},
                    {"fine_operator_seconds", r.fine_operator_seconds},
                    {"galerkin_naive_seconds", r.galerkin_naive_seconds},
                    {"galerkin_stream_seconds", r.galerkin_stream_seconds},
                    {"factor_seconds", r.factor_seconds},
                    {"solve_seconds", r.solve_seconds},
                    {"step_seconds", r.step_seconds},
                    {"step_cpu_seconds", r.step_cpu_seconds},
                    {"smoother_colors", r.smoother_colors},
                    {"smoother_clustered_vertices", r.smoother_clustered_vertices},
                    {"lexicographic_smoother", o.lexicographic},
                    {"feature_patch_max_valence", base.multigrid.patches.max_valence},
                    {"feature_patch_max_size", base.multigrid.patches.max_size},
                    {"adaptive_patch_rounds", base.multigrid.adaptive_patches.rounds},
                    {"feature_patches", r.feature_patches},
                    {"feature_patch_colors", r.feature_patch_colors},
                    {"boomeramg_available", r.external.available},
                    {"boomeramg_setup_seconds", r.external.setup_seconds},
                    {"boomeramg_solve_seconds", r.external.solve_seconds},
                    {"boomeramg_iterations", r.external.iterations},
                    {"boomeramg_converged", r.external.converged},
                    {"step_residual", r.step_residual},
                    {"newton_iterations", r.newton_iterations},
                    {"mg_pcg_seconds", r.mg_pcg_seconds},
                    {"mg_pcg_iterations", r.mg_pcg_iterations},
                    {"baseline_pcg_seconds", r.baseline_pcg_seconds},
                    {"baseline_pcg_iterations", r.baseline_pcg_iterations},
                    {"vcycles_to_tolerance", r.vcycles_to_tolerance},
                    {"vcycles_to_tolerance_seconds", r.vcycles_to_tolerance_seconds},
                    {"vcycle_rate", r.vcycle_rate},
                    {"stream_bytes", r.stream_bytes},
                    {"steps_per_second", r.steps_per_second},
                    {"baseline_steps_per_second", r.baseline_steps_per_second}});
    if (!o.json) {
      const std::string coarsest =
          std::to_string(r.levels) + " lv/" + std::to_string(r.level_vertices.back());
      char amg[64] = "-";
      if (r.external.available)
        std::snprintf(amg, sizeof amg, "%.0f+%.0f (%d)", 1e3 * r.external.setup_seconds,
                      1e3 * r.external.solve_seconds, r.external.iterations);
      char patches[32] = "-";  // patches (colours)
      if (r.feature_patches > 0)
        std::snprintf(patches, sizeof patches, "%d (%d)", r.feature_patches,
                      r.feature_patch_colors);
      std::printf(
          "%7d %6d %11s | %6.1f %6.1f | %6.1f %6.1f | %5.1f %5.1f %6.1f | %6.1f %6.1f %6.1f | "
          "%6.1f %6.1f | %5.2f %8.1e | %4.0f %4.0f %4.0f %4.0f %4.0f %4.0f | %14s | %9s | %5.1f  "
          "%s\n",
          r.tets, r.vertices, coarsest.c_str(), 1e3 * r.rotate_seconds, 1e3 * r.assemble_seconds,
          1e3 * r.galerkin_naive_seconds, 1e3 * r.galerkin_stream_seconds,
          1e3 * r.fine_operator_seconds, 1e3 * r.factor_seconds, 1e3 * r.solve_seconds,
          1e3 * r.step_seconds, 1e3 * r.step_cpu_seconds, r.steps_per_second,
          r.baseline_steps_per_second, r.stream_bytes / 1e6, r.vcycle_rate, r.step_residual,
          1e3 * r.baseline_pcg_seconds, r.baseline_pcg_iterations, 1e3 * r.mg_pcg_seconds,
          r.mg_pcg_iterations, 1e3 * r.vcycles_to_tolerance_seconds, r.vcycles_to_tolerance, amg,
          patches, r.setup_seconds, r.mesh.c_str());
      std::fflush(stdout);
    }
  }
  if (o.json)
    std::cout << nlohmann::json{{"benchmark", "tet-step"},
                                {"tolerance", o.tolerance},
                                {"steps", o.steps},
                                {"runs", rows}}
                     .dump(2)
              << "\n";
}

// Issue 22's validation cases (validation/validation_suite.hpp) as a table or JSON.
void print_validation(const validation::ValidationReport& report) {
  for (const validation::ConvergenceSeries& s : report.series) {
    std::printf("%s, %s engine, nu = %.2f: %s (%s)\n", s.study.c_str(), s.engine.c_str(),
                s.poisson_ratio, s.quantity.c_str(), s.unit.c_str());
    std::printf("%6s %10s %13s %13s %10s %7s %10s %9s\n", "n", "h", "value", "reference",
                "rel. error", "order", "unknowns", "seconds");
    for (const validation::ConvergenceRow& r : s.rows)
      std::printf("%6d %10.4g %13.6e %13.6e %10.3e %7.2f %10zu %9.2f%s\n", r.resolution, r.h,
                  r.value, r.reference, r.relative_error, r.order, r.unknowns, r.seconds,
                  r.converged ? "" : "  NOT converged");
    std::printf("order: last pair %.2f, least-squares fit over all rows %.2f\n", s.observed_order,
                s.fitted_order);
    if (std::isfinite(s.richardson_value))
      std::printf(
          "Richardson (last three): order %.2f, extrapolated %.6e (%+.2f %% of reference)\n",
          s.richardson_order, s.richardson_value,
          s.rows.back().reference != 0 ? 100 * (s.richardson_value / s.rows.back().reference - 1)
                                       : 0.0);
    std::printf("note: %s\n\n", s.note.c_str());
  }
  if (report.patch.empty()) return;
  std::printf("patch_test: homogeneous strain, max relative error at free variables\n");
  std::printf("%6s %6s %12s %10s\n", "engine", "n", "max error", "unknowns");
  for (const validation::PatchTestResult& p : report.patch)
    std::printf("%6s %6d %12.3e %10zu%s\n", p.engine.c_str(), p.resolution, p.max_relative_error,
                p.unknowns, p.converged ? "" : "  NOT converged");
}

struct VtkBenchOptions {
  int size = 256;
  int repeat = 3;
  int threads = 0;
  std::string encoding = "binary";
  std::string dir;
  bool json = false;
};

// Seconds to write one synthetic lattice frame (.vti), best of `repeat`: wall and process CPU
// (all threads), with the file size and the rate of array bytes (Float32/UInt8) per wall second.
void run_vtk_bench(const VtkBenchOptions& o) {
  set_thread_count(o.threads);
  const io::ImageData image = io::synthetic_lattice_frame(o.size);
  const auto encoding = o.encoding == "ascii" ? io::VtkEncoding::ASCII : io::VtkEncoding::BINARY;
  const std::filesystem::path dir = o.dir.empty()
                                        ? std::filesystem::temp_directory_path() /
                                              ("mgelastic-bench-vtk-" + std::to_string(::getpid()))
                                        : std::filesystem::path(o.dir);
  const auto path = dir / "grid_0000.vti";
  double wall = 1e300, cpu = 1e300;
  for (int r = 0; r < std::max(1, o.repeat); ++r) {
    const double w0 = omp_get_wtime();
    const std::clock_t c0 = std::clock();
    io::write_vti(path, image, encoding);
    cpu = std::min(cpu, double(std::clock() - c0) / CLOCKS_PER_SEC);
    wall = std::min(wall, omp_get_wtime() - w0);
  }
  const double megabytes = double(std::filesystem::file_size(path)) / 1e6;
  const std::size_t n = o.size, points = (n + 1) * (n + 1) * (n + 1), cells = n * n * n;
  const double raw_megabytes = double(3 * points * 4 + cells * (1 + 4 + 4)) / 1e6;
  if (o.dir.empty()) std::filesystem::remove_all(dir);
  const nlohmann::json record = {{"size", o.size},
                                 {"encoding", o.encoding},
                                 {"threads", omp_get_max_threads()},
                                 {"seconds", wall},
                                 {"cpu_seconds", cpu},
                                 {"file_mb", megabytes},
                                 {"array_mb", raw_megabytes},
                                 {"array_mb_per_s", raw_megabytes / wall}};
  if (o.json) {
    std::cout << record.dump(2) << "\n";
    return;
  }
  std::printf(
      "%d^3 lattice frame (.vti, %s, %d threads): %.2f s wall, %.2f s CPU, %.1f MB file "
      "(%.1f MB of arrays, %.0f MB/s)\n",
      o.size, o.encoding.c_str(), omp_get_max_threads(), wall, cpu, megabytes, raw_megabytes,
      raw_megabytes / wall);
}

void register_bench_commands(CLI::App& app) {
  CLI::App* bench = app.add_subcommand("bench", "Solver benchmarks");
  bench->require_subcommand(1);
  static VtkBenchOptions vtk_options;
  CLI::App* vtk = bench->add_subcommand(
      "vtk", "Seconds to write one grid-engine lattice frame (.vti) of a synthetic n^3 lattice");
  vtk->add_option("--size", vtk_options.size, "Cells per axis")->check(CLI::Range(1, 2048));
  vtk->add_option("--repeat", vtk_options.repeat, "Writes; the best is reported");
  vtk->add_option("--threads", vtk_options.threads, "Threads (0 = default)");
  vtk->add_option("--encoding", vtk_options.encoding, "binary or ascii")
      ->check(CLI::IsMember({"binary", "ascii"}));
  vtk->add_option("--dir", vtk_options.dir, "Folder for the file (default: a temporary one)");
  vtk->add_flag("--json", vtk_options.json, "Print JSON instead of a line");
  vtk->callback([] { run_vtk_bench(vtk_options); });
  static BoxBenchOptions conv_options, cg_options;
  CLI::App* conv = bench->add_subcommand(
      "convergence", "Residual reduction per V(1,1) cycle on the paper's elastic box");
  add_box_options(conv, conv_options);
  conv->add_option("--cycles", conv_options.cycles, "Number of V-cycles");
  conv->add_option("--precision", conv_options.precision,
                   "float (mixed: solution in double), single (float only) or double");
  conv->add_option("--boundary-sweeps", conv_options.boundary_sweeps,
                   "Band Gauss-Seidel sweeps (0 = paper default for nu)");
  conv->callback([] {
    set_thread_count(conv_options.threads);
    const auto result = run_convergence(conv_options);
    if (conv_options.json) {
      std::cout << result.dump(2) << "\n";
    } else {
      print_convergence(result);
    }
  });
  static BoxBenchOptions profile_options;
  static std::vector<int> profile_sizes{32, 64, 128}, profile_threads{1, 2};
  profile_options.poisson = 0.48;
  profile_options.precision = "float";
  profile_options.cycles = 10;
  CLI::App* vcycle = bench->add_subcommand(
      "vcycle", "Seconds per subroutine and per V-cycle (paper Figs. 22-23) on the mixed box");
  vcycle->add_option("--sizes", profile_sizes, "Cells per axis (3D); 0 = no box");
  vcycle->add_option("--threads", profile_threads, "Thread counts to compare");
  vcycle->add_option("--poisson", profile_options.poisson, "Poisson ratio");
  vcycle->add_option("--clamp-cells", profile_options.clamp_cells, kClampCellsHelp);
  vcycle->add_option("--precision", profile_options.precision,
                     "float (mixed: solution in double), single (float only) or double");
  vcycle->add_option("--cycles", profile_options.cycles, "V-cycles per run");
  vcycle->add_option("--cycle", profile_options.cycle, "V or W");
  // Multigrid knobs for rate studies (MultigridOptions in grid/multigrid.hpp).
  vcycle->add_option("--boundary-sweeps", profile_options.boundary_sweeps,
                     "Band Gauss-Seidel sweeps per smoothing (0 = paper default for nu)");
  vcycle->add_option("--band-layers", profile_options.band_layers,
                     "Extra cell layers in the band (default: 1 for --mesh, 0 for the box)");
  vcycle->add_option("--local-corrections", profile_options.local_corrections,
                     "Exact box solves placed where a slow mode's residual sits, at most this "
                     "many (default: 4 for --mesh, the scenes' default, and 0 for the box)");
  vcycle->add_option("--relocation-sweeps", profile_options.relocation_sweeps,
                     "Fig. 8 band sweeps before restriction / after prolongation (default 2)");
  vcycle->add_option("--refinement-reduction", profile_options.refinement_reduction,
                     "Mixed precision: float cycles per refinement run until they reduce the "
                     "correction problem's residual by this factor (default 0.02; 1 = refine "
                     "after every cycle)");
  vcycle
      ->add_option("--smoother-order", profile_options.smoother_order,
                   "Band sweeps: block_local (each block's sweeps while in cache; auto = this "
                   "in 3D) or band_wide (sweep after sweep over the whole band, the paper's)")
      ->check(CLI::IsMember({"auto", "block_local", "band_wide"}));
  vcycle->add_option("--max-levels", profile_options.max_levels, "Levels at most (0 = no limit)");
  vcycle
      ->add_option("--coarse-dirichlet", profile_options.coarse_dirichlet,
                   "Coarse cells that are Dirichlet: any_child (the paper's) or every_child (a "
                   "clamp top between coarse faces stays free; pays only with a Galerkin coarse "
                   "operator)")
      ->check(CLI::IsMember({"any_child", "every_child"}));
  vcycle
      ->add_option("--coarsest-operator", profile_options.coarsest_operator,
                   "Coarsest level's operator: rediscretized, galerkin (P^T A P of the level "
                   "above, probed: small problems only) or galerkin_band (only its band rows); "
                   "with --max-levels 2 a two-level study of the coarse operator")
      ->check(CLI::IsMember({"rediscretized", "galerkin", "galerkin_band"}));
  vcycle
      ->add_option("--coarse-band-rows", profile_options.coarse_band_rows,
                   "Displacement terms of the coarse band rows: rediscretized (the paper's), "
                   "galerkin_coarsest or galerkin (every coarse level; P^T A P of the level "
                   "above, computed locally; smoothed levels keep theirs next to Dirichlet cells)")
      ->check(CLI::IsMember({"rediscretized", "galerkin_coarsest", "galerkin"}));
  vcycle->add_option("--residual-blocks", profile_options.residual_blocks,
                     "Print the N cubes of 8^3 cells holding most of the residual after the last "
                     "cycle (where a slow mode sits)");
  vcycle->add_option("--coarsest-min-cells", profile_options.coarsest_min_cells,
                     "Cells along the longest axis a coarse level keeps at least (default 16)");
  vcycle->add_option("--coarsest-max-boundary-fraction",
                     profile_options.coarsest_max_boundary_fraction,
                     "Stop before a level with more body cells next to the exterior (default 0.5)");
  vcycle->add_flag("--no-coarse-fill-weights", profile_options.no_coarse_fill_weights,
                   "The paper's unweighted coarse operator");
  vcycle->add_flag("--no-repair-coarse-cells", profile_options.no_repair_coarse_cells,
                   "Coarse typings without the repair of hinges and sheets");
  vcycle->add_flag("--no-misaligned-clamp-depth", profile_options.no_misaligned_clamp_depth,
                   "Coarse clamps at the finest depth only where a coarse wall is a finest wall");
  vcycle->add_flag("--json", profile_options.json, "Print JSON instead of a table");
  static std::vector<std::string> profile_meshes;
  static int profile_resolution = 128;
  vcycle->add_option("--mesh", profile_meshes,
                     "Surface meshes to profile as well (voxelized, lowest 5 % fixed, gravity)");
  vcycle->add_option("--resolution", profile_resolution,
                     "Cells along the longest axis of each --mesh");
  vcycle->add_flag("--error-history", profile_options.error_history,
                   "For each --mesh also the error per cycle against the converged solution "
                   "(a double solve to 1e-10; the residual of a zero start can grow while the "
                   "error falls)");
  vcycle->callback([] {
    std::vector<int> sizes = profile_sizes;  // --sizes 0: meshes only
    std::erase_if(sizes, [](int n) { return n <= 0; });
    run_vcycle_profile(sizes, profile_threads, profile_options, profile_meshes, profile_resolution);
  });
  static TetStepOptions tet_options;
  CLI::App* tet_step = bench->add_subcommand(
      "tet-step",
      "Tet engine ms per step (paper Table 1/2): rotate, assemble, Galerkin naive/stream, "
      "V-cycles, whole step; BJ-PCG, MG-PCG and V-cycles to tolerance as baselines");
  tet_step->add_option("--cells", tet_options.cells,
                       "Cubes across the 1 x 0.25 x 0.25 bar (24 n^3 tets); none with --cells 0");
  tet_step->add_option("--mesh", tet_options.meshes, "Tet mesh files (bottom 10 % fixed)");
  tet_step->add_option("--refine", tet_options.refine, "Uniform refinements of the mesh files");
  tet_step->add_option("--rotation", tet_options.rotation, "energy | polar | smoothed_polar")
      ->check(CLI::IsMember({"energy", "polar", "smoothed_polar"}));
  tet_step->add_option("--vcycles", tet_options.vcycles, "V-cycles per step");
  tet_step->add_flag("--symmetric", tet_options.symmetric,
                     "Symmetric Gauss-Seidel sweeps (forward + backward) as each smoothing step");
  tet_step->add_option("--patches", tet_options.patches,
                       "Feature patches VALENCE[,SIZE]: block solves around vertices in <= "
                       "VALENCE tets, SIZE (12) vertices each (e.g. 7 or 7,12; off by default)");
  tet_step
      ->add_option("--adaptive-patches", tet_options.adaptive_patches,
                   "At most ROUNDS rounds of adaptive patches at the first step (power iterations "
                   "of the V-cycle's error; tet/patch_seeds.hpp); 0 = off")
      ->check(CLI::Range(0, 100));
  tet_step->add_option("--steps", tet_options.steps, "Measured steps (after one warm-up)");
  tet_step->add_option("--tolerance", tet_options.tolerance,
                       "Relative residual of the baseline solves");
  tet_step->add_option("--threads", tet_options.threads, "Threads (0 = default)");
  tet_step->add_option("--coarsest", tet_options.coarsest,
                       "Coarsen until a level has <= this many vertices");
  tet_step->add_option("--cell-factor", tet_options.cell_factor,
                       "First coarse cube size / mean fine edge length");
  tet_step->add_flag(
      "--hypre", tet_options.hypre,
      "Also solve the last step matrix with hypre BoomerAMG-PCG (when built with it)");
  tet_step->add_flag("--lexicographic", tet_options.lexicographic,
                     "Serial point-block Gauss-Seidel in vertex order instead of the multicolour "
                     "cluster smoother");
  tet_step->add_flag("--steps-only", tet_options.steps_only,
                     "Time the steps only (no naive product, baselines or rate; for profiling)");
  tet_step->add_flag("--json", tet_options.json, "Print JSON instead of a table");
  tet_step->callback([] {
    if (tet_options.threads > 0) set_thread_count(tet_options.threads);
    TetStepOptions o = tet_options;
    std::erase_if(o.cells, [](int n) { return n == 0; });
    run_tet_step(o);
  });
  static validation::ValidationOptions validation_options;
  static bool validation_json = false, validation_quick = false;
  static int validation_threads = 0;
  static std::vector<int> sphere_grid, sphere_tet, cantilever_grid, cantilever_tet, patch_sizes,
      disc_sizes;
  CLI::App* valid = bench->add_subcommand(
      "validation",
      "Analytic and reference cases with observed orders (docs/validation.md): Lame sphere, "
      "cantilever (tip force, gravity), patch test, the paper's disc");
  valid->add_flag("--quick", validation_quick, "Small sizes (seconds, not minutes)");
  valid->add_option("--sphere-grid", sphere_grid, "Grid cells across the sphere (0 = skip)");
  valid->add_option("--sphere-tet", sphere_tet, "Tet cubes across the sphere (0 = skip)");
  valid->add_option("--cantilever-grid", cantilever_grid,
                    "Grid cells along the cantilever (0 = skip)");
  valid->add_option("--cantilever-tet", cantilever_tet,
                    "Tet cubes along the cantilever (0 = skip)");
  valid->add_option("--patch", patch_sizes, "Patch test cells across the cube (0 = skip)");
  valid->add_option("--disc", disc_sizes, "Disc cells across the unit square (0 = skip)");
  valid->add_option("--threads", validation_threads, "Worker threads (default: all)");
  valid->add_flag("--json", validation_json, "Print JSON instead of a table");
  valid->callback([] {
    set_thread_count(validation_threads);
    validation::ValidationOptions o =
        validation_quick ? validation::ValidationOptions::quick() : validation_options;
    const auto pick = [](std::vector<int>& target, std::vector<int> given) {
      if (given.empty()) return;
      std::erase_if(given, [](int n) { return n <= 0; });
      target = given;
    };
    pick(o.sphere_grid, sphere_grid);
    pick(o.sphere_tet, sphere_tet);
    pick(o.cantilever_grid, cantilever_grid);
    pick(o.cantilever_tet, cantilever_tet);
    pick(o.patch, patch_sizes);
    pick(o.disc, disc_sizes);
    const auto progress = [](const std::string& line) {
      std::fprintf(stderr, "validation: %s\n", line.c_str());
    };
    const validation::ValidationReport report = validation::run_validation(o, progress);
    if (validation_json) {
      std::cout << validation::to_json(report).dump(2) << "\n";
    } else {
      print_validation(report);
    }
  });
  static bool disc_json = false;
  CLI::App* disc = bench->add_subcommand(
      "disc-accuracy", "The paper's embedded disc accuracy study (Sec. 9.2), nu = 0.2 and 0.49");
  disc->add_flag("--json", disc_json, "Print JSON instead of a table");
  disc->callback([] { run_disc_accuracy(disc_json); });
  CLI::App* cgc = bench->add_subcommand(
      "cg", "Conjugate gradients on the non-augmented staggered system (Fig. 11 baseline)");
  add_box_options(cgc, cg_options);
  cgc->add_option("--tolerance", cg_options.tolerance, "Relative residual to reach");
  cgc->add_option("--precision", cg_options.precision,
                  "Multigrid precision: double (default) or float (mixed: residuals in double)");
  cgc->add_flag("--skip-cg", cg_options.skip_cg,
                "Leave out the unpreconditioned CG (hypre and multigrid only; for 128^3 and up)");
  cgc->callback([] {
    set_thread_count(cg_options.threads);
    const auto result = run_cg(cg_options);
    if (cg_options.json) {
      std::cout << result.dump(2) << "\n";
    } else {
      print_cg(result);
    }
  });
}

}  // namespace mgelastic::app
