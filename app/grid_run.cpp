#include "grid_run.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <type_traits>

#include "frame_files.hpp"
#include "interruption.hpp"
#include "mgelastic/core/error.hpp"
#include "mgelastic/core/timer.hpp"
#include "mgelastic/grid/backward_euler.hpp"
#include "mgelastic/grid/corotated_dynamics.hpp"
#include "mgelastic/grid/multigrid.hpp"
#include "mgelastic/grid/node_fields.hpp"
#include "mgelastic/grid/surface_interpolation.hpp"
#include "mgelastic/io/surface_mesh_writers.hpp"
#include "mgelastic/io/vtk_writers.hpp"
#include "mgelastic/scene/grid_setup.hpp"
#include "progress.hpp"
#include "run_checkpoints.hpp"

namespace mgelastic::app {
namespace {

template <typename Scalar>
io::ImageData grid_fields(const grid::Multigrid<3, Scalar>& mg, const grid::NodeDisplacement& u,
                          const scene::Scene& s) {
  const auto& level = mg.finest();
  std::vector<double> von_mises =
      grid::von_mises_stress(u, grid::Material{s.youngs_modulus, s.poisson_ratio});
  io::ImageData image;
  image.cells = level.lattice.cells;
  image.spacing = level.lattice.h;
  image.origin = level.lattice.origin;
  // Fields of a single-precision solve are stored as Float32: half the bytes to write.
  const auto real = std::is_same_v<Scalar, float> ? io::VtkScalar::FLOAT32 : io::VtkScalar::FLOAT64;
  image.point_data.push_back({"displacement", 3, u.values, real});
  io::DataArray type{"cell_type", 1, {}, io::VtkScalar::UINT8}, pressure{"pressure", 1, {}, real};
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
  image.cell_data = {type, pressure, {"von_mises", 1, von_mises, real}};
  return image;
}

// Writes one frame's files and the series so far; returns the frame's .pvd entries.
template <typename Scalar>
std::vector<io::SeriesEntry> write_frame(const grid::Multigrid<3, Scalar>& mg,
                                         const scene::GridSetup& setup, const scene::Scene& s,
                                         const std::filesystem::path& dir, int frame, double time) {
  const auto value = [&](int f, std::ptrdiff_t k) { return mg.solution(f, k); };
  const grid::NodeDisplacement u = grid::node_displacement<Scalar>(mg.finest(), value);
  std::vector<io::SeriesEntry> entries;
  if (wants(s, "vtk")) {
    const std::string name = frame_name("grid", frame, "vti");
    io::write_vti(dir / name, grid_fields(mg, u, s), vtk_encoding(s));
    entries.push_back({time, name, 0});
  }
  const auto& rest = setup.surface.vertices;
  grid::PointRows deformed;
  const auto method = s.surface_interpolation == "trilinear" ? grid::SurfaceInterpolation::TRILINEAR
                                                             : grid::SurfaceInterpolation::TRICUBIC;
  grid::displace_points(u, method, rest, deformed);
  const auto& triangles = setup.surface.triangles;
  if (wants(s, "vtk")) {
    const std::string name = frame_name("surface", frame, "vtp");
    io::DataArray displacement{"displacement", 3, {}};
    const grid::PointRows d = deformed - rest;
    displacement.values.assign(d.data(), d.data() + d.size());
    io::write_vtp(dir / name, deformed, triangles, {displacement}, vtk_encoding(s));
    entries.push_back({time, name, 1});
  }
  if (wants(s, "obj"))
    io::write_obj(dir / frame_name("surface", frame, "obj"), deformed, triangles);
  if (wants(s, "ply"))
    io::write_ply(dir / frame_name("surface", frame, "ply"), deformed, triangles, true);
  return entries;
}

// Checkpoint state of the grid engine (run_checkpoints.hpp): the multigrid's warm start (the
// finest level's unknowns, "grid.x0".."grid.x3") and the series. A later engine feature that
// carries more from frame to frame (e.g. velocities) adds its arrays here.
template <typename Scalar>
io::Checkpoint grid_checkpoint(const RunCheckpoints& checkpoints,
                               const grid::Multigrid<3, Scalar>& mg, int frame, double time,
                               const std::vector<io::SeriesEntry>& series) {
  io::Checkpoint c = checkpoints.begin(frame, time);
  const auto& x = mg.solution_state();
  for (std::size_t f = 0; f < x.size(); ++f) c.add<double>("grid.x" + std::to_string(f), x[f]);
  add_series(c, series);
  return c;
}

template <typename Scalar>
void restore_grid(const io::Checkpoint& c, grid::Multigrid<3, Scalar>& mg,
                  std::vector<io::SeriesEntry>& series) {
  typename grid::Multigrid<3, Scalar>::SolutionState x;
  for (std::size_t f = 0; f < x.size(); ++f)
    x[f] = c.get<double>("grid.x" + std::to_string(f),
                         static_cast<std::int64_t>(mg.solution_state()[f].size()));
  mg.set_solution_state(x);
  series = series_of(c);
}

// Checkpoint state of a dynamic run: the multigrid's unknowns as for statics, the face
// velocities ("grid.v0".."grid.v2") and the time of the last step.
template <typename Scalar>
io::Checkpoint dynamics_checkpoint(const RunCheckpoints& checkpoints,
                                   const grid::BackwardEuler<3, Scalar>& sim, int frame,
                                   const std::vector<io::SeriesEntry>& series) {
  io::Checkpoint c = grid_checkpoint(checkpoints, sim.multigrid(), frame, sim.time(), series);
  const auto& v = sim.velocity();
  for (std::size_t f = 0; f < v.size(); ++f) c.add<double>("grid.v" + std::to_string(f), v[f]);
  return c;
}

template <typename Scalar>
void restore_dynamics(const io::Checkpoint& c, grid::BackwardEuler<3, Scalar>& sim,
                      std::vector<io::SeriesEntry>& series) {
  restore_grid(c, sim.multigrid(), series);
  auto& v = sim.velocity();
  for (std::size_t f = 0; f < v.size(); ++f)
    v[f] = c.get<double>("grid.v" + std::to_string(f), static_cast<std::int64_t>(v[f].size()));
  sim.set_time(c.time);
}

struct Totals {
  int frames = 0, cycles = 0;
  double solve_seconds = 0, output_seconds = 0, worst_residual = 0;
};

// The end of a frame, common to static and dynamic runs: writes its files and the series so far,
// reports progress, hands the frame's state to the checkpoints. Returns true when the run must
// stop (SIGINT/SIGTERM), after saying so.
template <typename Scalar>
bool finish_frame(const grid::Multigrid<3, Scalar>& mg, const scene::GridSetup& setup,
                  const scene::Scene& s, const std::filesystem::path& dir, int frame, double time,
                  const char* status, std::vector<io::SeriesEntry>& series, Totals& totals,
                  Progress& progress, RunCheckpoints& checkpoints,
                  const std::function<io::Checkpoint()>& state) {
  Timer timer;
  for (const auto& e : write_frame(mg, setup, s, dir, frame, time)) series.push_back(e);
  if (!series.empty()) io::write_pvd(dir / "simulation.pvd", series);
  totals.output_seconds += timer.seconds();
  progress.update(frame + 1, status);
  ++totals.frames;
  const bool interrupted = interruption_requested();
  checkpoints.completed(state(), interrupted);
  if (interrupted) {
    progress.finish();
    std::printf("interrupted: stopped after frame %d of %d; every written frame is complete\n",
                frame + 1, s.time.frames);
  }
  return interrupted;
}

template <typename Scalar>
void simulate(const scene::Scene& s, const scene::GridSetup& setup,
              const std::filesystem::path& dir, double setup_seconds, RunCheckpoints& checkpoints) {
  grid::MultigridOptions options;
  options.boundary_sweeps = s.boundary_sweeps;
  options.band_layers = s.band_layers;
  options.cycle = s.cycle == "W" ? grid::CycleType::W : grid::CycleType::V;
  Timer timer;
  grid::Multigrid<3, Scalar> mg(setup.problem, options);
  const double hierarchy_seconds = timer.seconds();
  std::printf("hierarchy: %d levels, %zu unknowns, %.0f MB (%.2f s)\n", mg.levels(), mg.unknowns(),
              mg.bytes() / 1e6, hierarchy_seconds);
  std::vector<io::SeriesEntry> series;
  if (const io::Checkpoint* resume = checkpoints.resume_from()) {
    restore_grid(*resume, mg, series);
    std::printf("resumed from %s: frame %d (t = %.6g s) done\n", resume->source.c_str(),
                resume->frame, resume->time);
  }
  Progress progress("frames", s.time.frames);
  Totals totals;
  for (int frame = checkpoints.first_frame(); frame < s.time.frames; ++frame) {
    // Frame k shows the equilibrium at time (k + 1) dt (after the first interval).
    const double time = (frame + 1) * s.time.dt;
    grid::SolveReport report;
    try {
      if (setup.animated())
        mg.set_dirichlet_displacement(scene::dirichlet_displacement(setup, time));
      report = s.accelerate ? mg.solve_accelerated(s.tolerance, s.max_vcycles)
                            : mg.solve(s.tolerance, s.max_vcycles);
    } catch (const Error& e) {
      progress.finish();
      throw frame_failed(e, checkpoints, frame, time);
    }
    const double relative =
        report.residuals.front() > 0 ? report.residuals.back() / report.residuals.front() : 0.0;
    totals.cycles += report.cycles();
    totals.solve_seconds += report.seconds;
    totals.worst_residual = std::max(totals.worst_residual, relative);
    char status[160];
    std::snprintf(status, sizeof status, "t = %.3f s  %d cycles  relative residual %.2e%s", time,
                  report.cycles(), relative, report.converged ? "" : " (NOT converged)");
    if (finish_frame(mg, setup, s, dir, frame, time, status, series, totals, progress, checkpoints,
                     [&] { return grid_checkpoint(checkpoints, mg, frame, time, series); }))
      break;
  }
  progress.finish();
  const auto& ph = mg.phase_seconds();
  std::printf(
      "summary: %zu interior + %zu Dirichlet cells (lattice %d x %d x %d, h = %.4g m), %d levels, "
      "%d frames, %d %s-cycles%s, worst relative residual %.2e\n"
      "time: setup %.2f s, hierarchy %.2f s, solve %.2f s (boundary %.2f, interior %.2f, residual "
      "%.2f, transfers %.2f, coarse %.2f), output %.2f s\n",
      setup.interior_cells, setup.dirichlet_cells, setup.voxels.dims[0], setup.voxels.dims[1],
      setup.voxels.dims[2], setup.voxels.cell_size, mg.levels(), totals.frames, totals.cycles,
      s.cycle.c_str(), s.accelerate ? " (FGMRES-accelerated)" : "", totals.worst_residual,
      setup_seconds, hierarchy_seconds, totals.solve_seconds, ph.boundary_smoothing,
      ph.interior_smoothing, ph.residual, ph.restriction + ph.prolongation, ph.coarse_solve,
      totals.output_seconds);
  if (totals.worst_residual > s.tolerance)
    std::printf("warning: some frames did not reach the tolerance %.1e within %d cycles\n",
                s.tolerance, s.max_vcycles);
  std::printf("wrote %s\n", dir.string().c_str());
}

// Dynamic run (Sec. 8): `time.substeps` backward-Euler steps per frame, each with
// `time.vcycles_per_step` warm-started cycles (or cycles to the tolerance), keyframed regions
// moved to each step's time. A diverging step stops the run with the frames written so far.
template <typename Scalar>
void simulate_dynamic(const scene::Scene& s, const scene::GridSetup& setup,
                      const std::filesystem::path& dir, double setup_seconds,
                      RunCheckpoints& checkpoints) {
  grid::MultigridOptions options;
  options.boundary_sweeps = s.boundary_sweeps;
  options.band_layers = s.band_layers;
  options.cycle = s.cycle == "W" ? grid::CycleType::W : grid::CycleType::V;
  const grid::TimeStepOptions stepping{.dt = s.time.dt / s.time.substeps,
                                       .density = s.density,
                                       .damping = s.time.damping,
                                       .mass_damping = s.time.mass_damping,
                                       .vcycles_per_step = s.time.vcycles_per_step,
                                       .tolerance = s.tolerance,
                                       .max_vcycles = s.max_vcycles,
                                       .accelerate = s.accelerate};
  Timer timer;
  grid::BackwardEuler<3, Scalar> sim(setup.problem, stepping, options);
  const double hierarchy_seconds = timer.seconds();
  const auto& mg = sim.multigrid();
  std::printf(
      "hierarchy: %d levels, %zu unknowns, %.0f MB (%.2f s); backward Euler, step %.4g s "
      "(%d per frame), c = %.3g N/m^4, %s\n",
      mg.levels(), mg.unknowns(), mg.bytes() / 1e6, hierarchy_seconds, stepping.dt, s.time.substeps,
      sim.inertia(),
      s.time.vcycles_per_step > 0
          ? (std::to_string(s.time.vcycles_per_step) + " cycle(s) per step").c_str()
          : "cycles to the tolerance");
  const Eigen::Vector3d v0 = s.initial_velocity;
  if (v0.squaredNorm() > 0) sim.set_velocity([v0](const grid::Vec<3>&) { return v0; });
  std::vector<io::SeriesEntry> series;
  if (const io::Checkpoint* resume = checkpoints.resume_from()) {
    restore_dynamics(*resume, sim, series);
    std::printf("resumed from %s: frame %d (t = %.6g s) done\n", resume->source.c_str(),
                resume->frame, resume->time);
  }
  Progress progress("frames", s.time.frames);
  Totals totals;
  int steps = 0;
  double log_rate_sum = 0;
  for (int frame = checkpoints.first_frame(); frame < s.time.frames; ++frame) {
    double frame_worst = 0;
    for (int sub = 0; sub < s.time.substeps; ++sub) {
      const double next = sim.time() + stepping.dt;
      grid::SolveReport report;
      try {
        report =
            sim.step(setup.animated() ? scene::dirichlet_displacement(setup, next)
                                      : typename grid::BackwardEuler<3, Scalar>::VectorField{});
      } catch (const Error& e) {
        progress.finish();
        throw frame_failed(e, checkpoints, frame, next);
      }
      const double relative =
          report.residuals.front() > 0 ? report.residuals.back() / report.residuals.front() : 0.0;
      if (relative > 0 && report.cycles() > 0) {
        log_rate_sum += std::log(relative) / report.cycles();
        ++steps;
      }
      frame_worst = std::max(frame_worst, relative);
      totals.cycles += report.cycles();
      totals.solve_seconds += report.seconds;
    }
    totals.worst_residual = std::max(totals.worst_residual, frame_worst);
    const double time = sim.time();
    char status[160];
    std::snprintf(status, sizeof status, "t = %.3f s  worst step residual reduction %.2e", time,
                  frame_worst);
    if (finish_frame(mg, setup, s, dir, frame, time, status, series, totals, progress, checkpoints,
                     [&] { return dynamics_checkpoint(checkpoints, sim, frame, series); }))
      break;
  }
  progress.finish();
  const auto& ph = mg.phase_seconds();
  std::printf(
      "summary: %zu interior + %zu Dirichlet cells (lattice %d x %d x %d, h = %.4g m), %d levels, "
      "%d frames, %d steps, %d %s-cycles, residual reduction per cycle: mean %.3f, worst step "
      "%.3f\n"
      "time: setup %.2f s, hierarchy %.2f s, solve %.2f s = %.3f s/frame (boundary %.2f, interior "
      "%.2f, residual %.2f, transfers %.2f, coarse %.2f), output %.2f s\n",
      setup.interior_cells, setup.dirichlet_cells, setup.voxels.dims[0], setup.voxels.dims[1],
      setup.voxels.dims[2], setup.voxels.cell_size, mg.levels(), totals.frames,
      totals.frames * s.time.substeps, totals.cycles, s.cycle.c_str(),
      steps > 0 ? std::exp(log_rate_sum / steps) : 0.0, totals.worst_residual, setup_seconds,
      hierarchy_seconds, totals.solve_seconds,
      totals.frames > 0 ? totals.solve_seconds / totals.frames : 0.0, ph.boundary_smoothing,
      ph.interior_smoothing, ph.residual, ph.restriction + ph.prolongation, ph.coarse_solve,
      totals.output_seconds);
  std::printf("wrote %s\n", dir.string().c_str());
}

// Co-rotational model (Sec. 7, `material.model: corotated`): the same runs on the co-rotated
// multigrid (double precision, `solver.corotated_smoother`, rotations refreshed every
// `time.rotation_update_every` cycles). Progress and summary report the true non-linear residual
// (the convergence test) and the quasi-linear residual of the last frozen system.
grid::CorotatedOptions corotated_options(const scene::Scene& s) {
  grid::CorotatedOptions options;
  options.rotation_update_every = s.time.rotation_update_every;
  options.smoother = s.corotated_smoother == "distributive" ? grid::CorotatedSmoother::DISTRIBUTIVE
                                                            : grid::CorotatedSmoother::BOX;
  return options;
}

grid::MultigridOptions multigrid_options(const scene::Scene& s) {
  grid::MultigridOptions options;
  options.boundary_sweeps = s.boundary_sweeps;
  options.band_layers = s.band_layers;
  options.cycle = s.cycle == "W" ? grid::CycleType::W : grid::CycleType::V;
  return options;
}

// Checkpoint state of a co-rotated run beyond the unknowns (CorotatedCarriedState): the finest
// rotations the frozen rows were built from ("grid.rotations"), the cycles since their refresh
// ("grid.corotated_cycles"), the Newton step's recycled corrections ("grid.recycled0", ...).
void add_corotated(io::Checkpoint& c, const grid::CorotatedMultigrid<3>& solver) {
  const grid::CorotatedCarriedState<3> state = solver.carried_state();
  c.add<double>("grid.rotations", state.rotations);
  const std::vector<std::int64_t> counters{state.cycles_since_refresh,
                                           static_cast<std::int64_t>(state.recycled.size())};
  c.add<std::int64_t>("grid.corotated_cycles", counters);
  for (std::size_t i = 0; i < state.recycled.size(); ++i)
    c.add<double>("grid.recycled" + std::to_string(i),
                  std::span<const double>(state.recycled[i].data(), state.recycled[i].size()));
}

void restore_corotated(const io::Checkpoint& c, grid::CorotatedMultigrid<3>& solver) {
  grid::CorotatedCarriedState<3> state;
  state.rotations = c.get<double>("grid.rotations");
  const auto counters = c.get<std::int64_t>("grid.corotated_cycles", 2);
  state.cycles_since_refresh = static_cast<int>(counters[0]);
  for (std::int64_t i = 0; i < counters[1]; ++i) {
    const auto z = c.get<double>("grid.recycled" + std::to_string(i));
    state.recycled.emplace_back(Eigen::Map<const Eigen::VectorXd>(z.data(), z.size()));
  }
  try {
    solver.restore_carried_state(state);
  } catch (const Error& e) {
    throw Error(e.reason(), ErrorContext{.file = c.source});
  }
}

double reduction(const std::vector<double>& residuals) {
  return residuals.front() > 0 ? residuals.back() / residuals.front() : 0.0;
}

void simulate_corotated(const scene::Scene& s, const scene::GridSetup& setup,
                        const std::filesystem::path& dir, double setup_seconds,
                        RunCheckpoints& checkpoints) {
  Timer timer;
  grid::CorotatedMultigrid<3> solver(setup.problem, multigrid_options(s), corotated_options(s));
  const double hierarchy_seconds = timer.seconds();
  auto& mg = solver.linear_hierarchy();
  std::printf(
      "hierarchy: %d levels, %zu unknowns (%.2f s); co-rotated model, rotations refreshed every "
      "%d cycles\n",
      solver.levels(), solver.unknowns(), hierarchy_seconds, s.time.rotation_update_every);
  std::vector<io::SeriesEntry> series;
  if (const io::Checkpoint* resume = checkpoints.resume_from()) {
    restore_grid(*resume, mg, series);
    restore_corotated(*resume, solver);
    std::printf("resumed from %s: frame %d (t = %.6g s) done\n", resume->source.c_str(),
                resume->frame, resume->time);
  }
  Progress progress("frames", s.time.frames);
  Totals totals;
  double last_quasi_linear = 0;
  for (int frame = checkpoints.first_frame(); frame < s.time.frames; ++frame) {
    const double time = (frame + 1) * s.time.dt;
    grid::CorotatedReport report;
    try {
      if (setup.animated())
        solver.set_dirichlet_displacement(scene::dirichlet_displacement(setup, time));
      report = solver.solve_with_load_steps(s.tolerance, s.max_vcycles);
    } catch (const Error& e) {
      progress.finish();
      throw frame_failed(e, checkpoints, frame, time);
    }
    const double relative = reduction(report.nonlinear);
    last_quasi_linear = report.quasi_linear.back();
    totals.cycles += report.cycles();
    totals.solve_seconds += report.seconds;
    totals.worst_residual = std::max(totals.worst_residual, relative);
    char status[200];
    std::snprintf(status, sizeof status,
                  "t = %.3f s  %d cycles  relative non-linear residual %.2e (quasi-linear "
                  "%.2e)%s",
                  time, report.cycles(), relative, reduction(report.quasi_linear),
                  report.converged ? "" : " (NOT converged)");
    if (finish_frame(mg, setup, s, dir, frame, time, status, series, totals, progress, checkpoints,
                     [&] {
                       io::Checkpoint c = grid_checkpoint(checkpoints, mg, frame, time, series);
                       add_corotated(c, solver);
                       return c;
                     }))
      break;
  }
  progress.finish();
  std::printf(
      "summary: %zu interior + %zu Dirichlet cells (lattice %d x %d x %d, h = %.4g m), %d levels, "
      "co-rotated model, %d frames, %d cycles, worst relative non-linear residual %.2e, last "
      "quasi-linear residual %.2e\n"
      "time: setup %.2f s, hierarchy %.2f s, solve %.2f s, output %.2f s\n",
      setup.interior_cells, setup.dirichlet_cells, setup.voxels.dims[0], setup.voxels.dims[1],
      setup.voxels.dims[2], setup.voxels.cell_size, solver.levels(), totals.frames, totals.cycles,
      totals.worst_residual, last_quasi_linear, setup_seconds, hierarchy_seconds,
      totals.solve_seconds, totals.output_seconds);
  if (totals.worst_residual > s.tolerance)
    std::printf("warning: some frames did not reach the tolerance %.1e within %d cycles\n",
                s.tolerance, s.max_vcycles);
  std::printf("wrote %s\n", dir.string().c_str());
}

void simulate_corotated_dynamic(const scene::Scene& s, const scene::GridSetup& setup,
                                const std::filesystem::path& dir, double setup_seconds,
                                RunCheckpoints& checkpoints) {
  const grid::TimeStepOptions stepping{.dt = s.time.dt / s.time.substeps,
                                       .density = s.density,
                                       .damping = s.time.damping,
                                       .mass_damping = s.time.mass_damping,
                                       .vcycles_per_step = s.time.vcycles_per_step,
                                       .tolerance = s.tolerance,
                                       .max_vcycles = s.max_vcycles};
  Timer timer;
  grid::CorotatedBackwardEuler<3> sim(setup.problem, stepping, multigrid_options(s),
                                      corotated_options(s));
  const double hierarchy_seconds = timer.seconds();
  auto& mg = sim.multigrid().linear_hierarchy();
  std::printf(
      "hierarchy: %d levels, %zu unknowns (%.2f s); co-rotated model, rotations refreshed every "
      "%d cycles; backward Euler, step %.4g s (%d per frame)\n",
      sim.multigrid().levels(), sim.multigrid().unknowns(), hierarchy_seconds,
      s.time.rotation_update_every, stepping.dt, s.time.substeps);
  const Eigen::Vector3d v0 = s.initial_velocity;
  if (v0.squaredNorm() > 0) sim.set_velocity([v0](const grid::Vec<3>&) { return v0; });
  std::vector<io::SeriesEntry> series;
  auto checkpoint = [&](int frame) {
    io::Checkpoint c = grid_checkpoint(checkpoints, mg, frame, sim.time(), series);
    const auto& v = sim.velocity();
    for (std::size_t f = 0; f < v.size(); ++f) c.add<double>("grid.v" + std::to_string(f), v[f]);
    add_corotated(c, sim.multigrid());
    return c;
  };
  if (const io::Checkpoint* resume = checkpoints.resume_from()) {
    restore_grid(*resume, mg, series);
    auto& v = sim.velocity();
    for (std::size_t f = 0; f < v.size(); ++f)
      v[f] =
          resume->get<double>("grid.v" + std::to_string(f), static_cast<std::int64_t>(v[f].size()));
    sim.set_time(resume->time);
    restore_corotated(*resume, sim.multigrid());
    std::printf("resumed from %s: frame %d (t = %.6g s) done\n", resume->source.c_str(),
                resume->frame, resume->time);
  }
  Progress progress("frames", s.time.frames);
  Totals totals;
  int steps = 0;
  double log_rate_sum = 0, last_quasi_linear = 0;
  for (int frame = checkpoints.first_frame(); frame < s.time.frames; ++frame) {
    double frame_worst = 0;
    for (int sub = 0; sub < s.time.substeps; ++sub) {
      const double next = sim.time() + stepping.dt;
      grid::CorotatedReport report;
      try {
        report = sim.step(setup.animated() ? scene::dirichlet_displacement(setup, next)
                                           : grid::CorotatedBackwardEuler<3>::VectorField{});
      } catch (const Error& e) {
        progress.finish();
        throw frame_failed(e, checkpoints, frame, next);
      }
      const double relative = reduction(report.nonlinear);
      last_quasi_linear = report.quasi_linear.back();
      if (relative > 0 && report.cycles() > 0) {
        log_rate_sum += std::log(relative) / report.cycles();
        ++steps;
      }
      frame_worst = std::max(frame_worst, relative);
      totals.cycles += report.cycles();
      totals.solve_seconds += report.seconds;
    }
    totals.worst_residual = std::max(totals.worst_residual, frame_worst);
    const double time = sim.time();
    char status[160];
    std::snprintf(status, sizeof status,
                  "t = %.3f s  worst step non-linear residual reduction %.2e", time, frame_worst);
    if (finish_frame(mg, setup, s, dir, frame, time, status, series, totals, progress, checkpoints,
                     [&] { return checkpoint(frame); }))
      break;
  }
  progress.finish();
  std::printf(
      "summary: %zu interior + %zu Dirichlet cells (lattice %d x %d x %d, h = %.4g m), %d levels, "
      "co-rotated model, %d frames, %d steps, %d cycles, non-linear residual reduction per "
      "cycle: mean %.3f, worst step %.3f, last quasi-linear residual %.2e\n"
      "time: setup %.2f s, hierarchy %.2f s, solve %.2f s = %.3f s/frame, output %.2f s\n",
      setup.interior_cells, setup.dirichlet_cells, setup.voxels.dims[0], setup.voxels.dims[1],
      setup.voxels.dims[2], setup.voxels.cell_size, sim.multigrid().levels(), totals.frames,
      totals.frames * s.time.substeps, totals.cycles,
      steps > 0 ? std::exp(log_rate_sum / steps) : 0.0, totals.worst_residual, last_quasi_linear,
      setup_seconds, hierarchy_seconds, totals.solve_seconds,
      totals.frames > 0 ? totals.solve_seconds / totals.frames : 0.0, totals.output_seconds);
  std::printf("wrote %s\n", dir.string().c_str());
}
}  // namespace

void run_grid_scene(const scene::Scene& s, const std::filesystem::path& dir,
                    RunCheckpoints& checkpoints) {
  if (!s.time.quasistatic && s.time.integrator != "implicit_euler")
    throw Error("the grid engine integrates with implicit_euler (backward Euler, Sec. 8) only",
                ErrorContext{.file = s.file, .pointer = "/time/integrator"});
  Timer timer;
  const scene::GridSetup setup = scene::build_grid_setup(s);
  const double setup_seconds = timer.seconds();
  std::printf(
      "scene %s: %zu interior cells, %zu Dirichlet cells, lattice %d x %d x %d, surface %td "
      "triangles%s\n",
      s.file.c_str(), setup.interior_cells, setup.dirichlet_cells, setup.voxels.dims[0],
      setup.voxels.dims[1], setup.voxels.dims[2], setup.surface.triangle_count(),
      setup.traction_triangles ? " (some under traction)" : "");
  if (s.material_model == "corotated") {
    if (s.time.quasistatic) {
      simulate_corotated(s, setup, dir, setup_seconds, checkpoints);
    } else {
      simulate_corotated_dynamic(s, setup, dir, setup_seconds, checkpoints);
    }
  } else if (!s.time.quasistatic) {
    if (s.precision == "double") {
      simulate_dynamic<double>(s, setup, dir, setup_seconds, checkpoints);
    } else {
      simulate_dynamic<float>(s, setup, dir, setup_seconds, checkpoints);
    }
  } else if (s.precision == "double") {
    simulate<double>(s, setup, dir, setup_seconds, checkpoints);
  } else {
    simulate<float>(s, setup, dir, setup_seconds, checkpoints);
  }
}

}  // namespace mgelastic::app
