#include "run_command.hpp"

#include <cstdio>
#include <filesystem>

#include "mgelastic/core/error.hpp"
#include "mgelastic/core/threads.hpp"
#include "mgelastic/core/timer.hpp"
#include "mgelastic/grid/multigrid.hpp"
#include "mgelastic/grid/node_fields.hpp"
#include "mgelastic/io/vtk_writers.hpp"
#include "mgelastic/scene/grid_setup.hpp"
#include "mgelastic/scene/scene.hpp"

namespace mgelastic::app {
namespace {

struct RunOptions {
  std::string scene;
  std::string output;
  int threads = 0;
};

template <typename Scalar>
void write_grid_fields(const grid::Multigrid<3, Scalar>& mg, const scene::Scene& s,
                       const std::filesystem::path& dir) {
  const auto& level = mg.finest();
  const auto value = [&](int f, std::ptrdiff_t k) { return mg.solution(f, k); };
  const grid::NodeDisplacement u = grid::node_displacement<Scalar>(level, value);
  const grid::Material material{s.youngs_modulus, s.poisson_ratio};
  std::vector<double> von_mises = grid::von_mises_stress(u, material);
  io::ImageData image;
  image.cells = level.lattice.cells;
  image.spacing = level.lattice.h;
  image.origin = level.lattice.origin;
  image.point_data.push_back({"displacement", 3, u.values});
  io::DataArray type{"cell_type", 1, {}}, pressure{"pressure", 1, {}};
  const auto& n = level.lattice.cells;
  std::size_t c = 0;
  for (int k = 1; k <= n[2]; ++k)
    for (int j = 1; j <= n[1]; ++j)
      for (int i = 1; i <= n[0]; ++i, ++c) {
        const std::ptrdiff_t cell = level.lattice.index(grid::IVec<3>(i, j, k));
        const bool interior = level.cells[cell] == grid::CellType::INTERIOR;
        type.values.push_back(static_cast<double>(level.cells[cell]));
        pressure.values.push_back(interior ? mg.solution(3, cell) : 0.0);
        if (level.cells[cell] == grid::CellType::EXTERIOR) von_mises[c] = 0.0;
      }
  image.cell_data = {type, pressure, {"von_mises", 1, von_mises}};
  io::write_vti(dir / "grid_0000.vti", image);
  io::write_pvd(dir / "simulation.pvd", {{0.0, "grid_0000.vti", 0}});
}

template <typename Scalar>
void solve_and_write(const scene::Scene& s, const scene::GridSetup& setup,
                     const std::filesystem::path& dir, double setup_seconds) {
  grid::MultigridOptions options;
  options.boundary_sweeps = s.boundary_sweeps;
  options.cycle = s.cycle == "W" ? grid::CycleType::W : grid::CycleType::V;
  Timer timer;
  grid::Multigrid<3, Scalar> mg(setup.problem, options);
  const double hierarchy_seconds = timer.seconds();
  std::printf("hierarchy: %d levels, %zu unknowns (%.2f s)\n", mg.levels(), mg.unknowns(),
              hierarchy_seconds);
  const grid::SolveReport report = s.accelerate ? mg.solve_accelerated(s.tolerance, s.max_vcycles)
                                                : mg.solve(s.tolerance, s.max_vcycles);
  for (std::size_t k = 1; k < report.residuals.size(); ++k)
    std::printf("  cycle %3zu  residual %.3e  ratio %.3f\n", k, report.residuals[k],
                report.residuals[k] / report.residuals[k - 1]);
  if (!report.converged)
    std::printf("warning: relative residual %.2e after %d cycles (tolerance %.1e)\n",
                report.residuals.back() / report.residuals.front(), report.cycles(), s.tolerance);
  timer.restart();
  const bool vtk = std::find(s.formats.begin(), s.formats.end(), "vtk") != s.formats.end();
  if (vtk) write_grid_fields(mg, s, dir);
  const double output_seconds = timer.seconds();
  const auto& ph = mg.phase_seconds();
  std::printf(
      "summary: %zu interior + %zu Dirichlet cells (lattice %d x %d x %d, h = %.4g m), %d levels, "
      "%d %s-cycles%s, relative residual %.2e\n"
      "time: setup %.2f s, hierarchy %.2f s, solve %.2f s (boundary %.2f, interior %.2f, residual "
      "%.2f, transfers %.2f, coarse %.2f), output %.2f s\n",
      setup.interior_cells, setup.dirichlet_cells, setup.voxels.dims[0], setup.voxels.dims[1],
      setup.voxels.dims[2], setup.voxels.cell_size, mg.levels(), report.cycles(), s.cycle.c_str(),
      s.accelerate ? " (FGMRES-accelerated)" : "",
      report.residuals.back() / report.residuals.front(), setup_seconds, hierarchy_seconds,
      report.seconds, ph.boundary_smoothing, ph.interior_smoothing, ph.residual,
      ph.restriction + ph.prolongation, ph.coarse_solve, output_seconds);
  if (vtk) std::printf("wrote %s\n", (dir / "simulation.pvd").string().c_str());
  for (const auto& f : s.formats)
    if (f != "vtk")
      std::printf("note: output format '%s' (deformed surface) is not implemented yet\n",
                  f.c_str());
}

}  // namespace

void run_scene(const scene::Scene& s, const std::filesystem::path& output) {
  if (s.engine != "grid")
    throw Error("engine '" + s.engine + "' is not available in `mgelastic run` yet (grid only)",
                ErrorContext{.file = s.file, .pointer = "/engine"});
  if (!s.tractions.empty())
    throw Error("surface tractions in scenes are not implemented yet",
                ErrorContext{.file = s.file, .pointer = "/loads/tractions"});
  Timer timer;
  const scene::GridSetup setup = scene::build_grid_setup(s);
  const double setup_seconds = timer.seconds();
  const std::filesystem::path dir = output.empty() ? std::filesystem::path(s.output_dir) : output;
  std::printf("scene %s: %zu interior cells, %zu Dirichlet cells, lattice %d x %d x %d\n",
              s.file.c_str(), setup.interior_cells, setup.dirichlet_cells, setup.voxels.dims[0],
              setup.voxels.dims[1], setup.voxels.dims[2]);
  if (s.precision == "double") {
    solve_and_write<double>(s, setup, dir, setup_seconds);
  } else {
    solve_and_write<float>(s, setup, dir, setup_seconds);
  }
}

namespace {

void run(const RunOptions& o) {
  set_thread_count(o.threads);
  run_scene(scene::load_scene(o.scene), o.output);
}

}  // namespace

void register_run_command(CLI::App& app) {
  static RunOptions options;
  CLI::App* cmd = app.add_subcommand("run", "Simulate a scene (grid engine, quasistatic)");
  cmd->add_option("scene", options.scene, "Scene file (JSON)")->required();
  cmd->add_option("--output", options.output, "Output directory (default: the scene's output.dir)");
  cmd->add_option("--threads", options.threads, "Worker threads (default: all cores)");
  cmd->callback([] { run(options); });
}

}  // namespace mgelastic::app
