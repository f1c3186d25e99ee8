#include "run_printer.hpp"

#include <cmath>
#include <cstdio>
#include <string>

#include "interruption.hpp"

namespace mgelastic::app {
namespace {

const char* rotation_name(tet::RotationMethod method) {
  switch (method) {
    case tet::RotationMethod::POLAR:
      return "polar decomposition";
    case tet::RotationMethod::POLAR_SMOOTHED:
      return "smoothed polar decomposition";
    case tet::RotationMethod::ENERGY_MINIMIZATION:
      break;
  }
  return "energy minimization";
}

const char* iteration_name(tet::LinearSolver kind) {
  return kind == tet::LinearSolver::MULTIGRID ? " V-cycles"
         : kind == tet::LinearSolver::MG_PCG  ? " MG-PCG iterations"
                                              : " PCG iterations";
}

void print_grid_setup(const scene::Scene& s, const sim::GridStepper& grid) {
  const scene::GridSetup& setup = grid.setup();
  std::printf(
      "scene %s: %zu interior cells, %zu Dirichlet cells, lattice %d x %d x %d, surface %td "
      "triangles%s\n",
      s.file.c_str(), setup.interior_cells, setup.dirichlet_cells, setup.voxels.dims[0],
      setup.voxels.dims[1], setup.voxels.dims[2], setup.surface.triangle_count(),
      setup.traction_triangles ? " (some under traction)" : "");
  const bool corotated = s.material_model == "corotated";
  std::string model = corotated ? "; co-rotated model, rotations refreshed every " +
                                      std::to_string(s.time.rotation_update_every) + " cycles"
                                : "";
  if (!s.time.quasistatic) {
    char text[200];
    std::snprintf(text, sizeof text, "; backward Euler, step %.4g s (%d per frame)%s",
                  grid.step_dt(), s.time.substeps, corotated ? "" : ", c = ");
    model += text;
    if (!corotated) {
      std::snprintf(text, sizeof text, "%.3g N/m^4, %s", grid.inertia(),
                    s.time.vcycles_per_step > 0
                        ? (std::to_string(s.time.vcycles_per_step) + " cycle(s) per step").c_str()
                        : "cycles to the tolerance");
      model += text;
    }
  }
  if (grid.bytes() > 0)
    std::printf("hierarchy: %d levels, %zu unknowns, %.0f MB (%.2f s)%s\n", grid.levels(),
                grid.unknowns(), grid.bytes() / 1e6, grid.hierarchy_seconds(), model.c_str());
  else
    std::printf("hierarchy: %d levels, %zu unknowns (%.2f s)%s\n", grid.levels(), grid.unknowns(),
                grid.hierarchy_seconds(), model.c_str());
}

void print_tet_setup(const scene::Scene& s, const sim::TetStepper& tet) {
  const scene::TetSetup& setup = tet.setup();
  const tet::LinearSolver kind = setup.settings.linear_solver;
  const char* solver_name = kind == tet::LinearSolver::MULTIGRID  ? "multigrid V-cycles"
                            : kind == tet::LinearSolver::MG_PCG   ? "multigrid-preconditioned CG"
                            : kind != tet::LinearSolver::CHOLESKY ? "block-Jacobi PCG"
                                                                  : "sparse Cholesky";
  char mesh[160] = "", stepping[160] = "quasistatic (one equilibrium per frame)";
  std::snprintf(mesh, sizeof mesh, "%s", setup.mesh_source.c_str());
  if (setup.cell_size > 0)
    std::snprintf(mesh, sizeof mesh, "%s, cube edge %.4g m", setup.mesh_source.c_str(),
                  setup.cell_size);
  char embedded[200] = " (boundary of the tets)";
  if (setup.cell_size > 0)
    std::snprintf(embedded, sizeof embedded,
                  " (input surface embedded in the tets: %td vertices, %d outside any tet, up to "
                  "%.3g m; surface %.3f s, embedding %.3f s)",
                  setup.surface.vertex_count(), setup.surface.outside_vertices,
                  setup.surface.max_outside_distance, setup.surface_seconds, setup.embed_seconds);
  if (!s.time.quasistatic)
    std::snprintf(stepping, sizeof stepping, "dynamic, %d %s step(s) of %.4g s per frame",
                  s.time.substeps, s.time.integrator.c_str(), setup.settings.time_step);
  std::printf(
      "scene %s: tet engine, %d vertices, %d tets (%s), %zu Dirichlet vertices, %td surface "
      "triangles%s\n"
      "  %s, rotations by %s, %s, %d frames of %.4g s\n",
      s.file.c_str(), setup.mesh.vertex_count(), setup.mesh.tet_count(), mesh,
      setup.dirichlet_vertices.size(), setup.surface.triangles.rows(), embedded, stepping,
      rotation_name(setup.settings.rotation_method), solver_name, s.time.frames, s.time.dt);
}

// Why a grid frame stopped short of its tolerance without using up its cycles.
const char* stall_note(const std::string& precision) {
  return precision == "single" ? " (NOT converged: stalled at float round-off)"
                               : " (NOT converged: stalled at the round-off floor of double "
                                 "precision)";
}

// Why frames stopped short of the tolerance: the cycle limit, or round-off.
std::string unreached_tolerance_reason(const scene::Scene& s, bool stalled) {
  if (!stalled) return "the cycle limit " + std::to_string(s.max_vcycles) + " came first";
  if (s.precision == "single")
    return "the residual stalled at float round-off (single precision; \"float\" reaches it "
           "with the same float cycles)";
  return "the residual stalled at the round-off floor of x in double precision (~eps |A| |x|, "
         "which grows with the resolution): ask for a tolerance above the residual reached";
}

}  // namespace

void print_setup(const sim::Simulation& simulation, double) {
  if (const auto* grid = simulation.grid())
    print_grid_setup(simulation.scene(), *grid);
  else
    print_tet_setup(simulation.scene(), *simulation.tet());
  std::fflush(stdout);
}

RunPrinter::RunPrinter(const scene::Scene& scene, std::filesystem::path dir,
                       sim::RunCheckpoints& checkpoints)
    : sim::OutputObserver(scene, std::move(dir), checkpoints),
      m_progress("frames", scene.time.frames) {
  stop_requested = [] { return interruption_requested(); };
}

bool RunPrinter::frame_done(const sim::Simulation& simulation, const sim::FrameStats& stats) {
  const bool go_on = sim::OutputObserver::frame_done(simulation, stats);
  const scene::Scene& s = simulation.scene();
  ++m_frames;
  m_unconverged += stats.converged ? 0 : 1;
  for (const sim::StepStats& step : stats.step_stats) m_stalled += step.stalled ? 1 : 0;
  m_total.steps += stats.steps;
  m_total.cycles += stats.cycles;
  m_total.worst_residual = std::max(m_total.worst_residual, stats.worst_residual);
  m_total.solve_seconds += stats.solve_seconds;
  m_total.rotate_seconds += stats.rotate_seconds;
  m_total.assemble_seconds += stats.assemble_seconds;
  for (const sim::StepStats& step : stats.step_stats) {
    if (step.relative_residual > 0 && step.cycles > 0) {
      m_log_rate_sum += std::log(step.relative_residual) / step.cycles;
      ++m_rate_steps;
    }
    m_last_quasi_linear = step.quasi_linear_residual;
  }
  if (const auto* tet = simulation.tet()) {
    const tet::LinearSolver kind = tet->setup().settings.linear_solver;
    const std::string iterations = kind != tet::LinearSolver::CHOLESKY
                                       ? "  " + std::to_string(stats.cycles) + iteration_name(kind)
                                       : std::string();
    std::printf(
        "frame %4d/%d  t = %.4f s  %d %s%s  residual %.2e%s  rotate %.3f s  assemble %.3f s  "
        "solve %.3f s  output %.3f s\n",
        stats.frame + 1, s.time.frames, stats.time, stats.steps,
        s.time.quasistatic ? "rounds" : "steps", iterations.c_str(), stats.worst_residual,
        stats.converged ? "" : " (NOT converged)", stats.rotate_seconds, stats.assemble_seconds,
        stats.solve_seconds, last_output_seconds());
    std::fflush(stdout);
  } else {
    char status[200];
    const sim::StepStats& last = stats.step_stats.back();
    const bool corotated = s.material_model == "corotated";
    if (!s.time.quasistatic)
      std::snprintf(status, sizeof status, "t = %.3f s  worst step %sresidual reduction %.2e",
                    stats.time, corotated ? "non-linear " : "", stats.worst_residual);
    else if (corotated)
      std::snprintf(status, sizeof status,
                    "t = %.3f s  %d cycles  relative non-linear residual %.2e (quasi-linear "
                    "%.2e)%s",
                    stats.time, stats.cycles, last.relative_residual, last.quasi_linear_reduction,
                    stats.converged ? "" : " (NOT converged)");
    else
      std::snprintf(status, sizeof status, "t = %.3f s  %d cycles  relative residual %.2e%s",
                    stats.time, stats.cycles, last.relative_residual,
                    stats.converged ? ""
                    : last.stalled  ? stall_note(s.precision)
                                    : " (NOT converged)");
    m_progress.update(stats.frame + 1, status);
  }
  if (!go_on) {
    m_progress.finish();
    std::printf("interrupted: stopped after frame %d of %d; every written frame is complete\n",
                stats.frame + 1, s.time.frames);
  }
  return go_on;
}

void RunPrinter::cancelled(const sim::Simulation& simulation, sim::RunCheckpoints& checkpoints) {
  m_progress.finish();
  checkpoints.save_last_good();
  std::printf("interrupted: stopped after frame %d of %d; every written frame is complete\n",
              simulation.frame(), simulation.frames());
}

Error RunPrinter::frame_failed(const sim::Simulation& simulation, const Error& error) {
  m_progress.finish();
  return sim::OutputObserver::frame_failed(simulation, error);
}

namespace {

// The last frame's probes and reactions (all frames: probes.csv).
void print_probes(const scene::Scene& s, const sim::ProbeTable& table) {
  if (table.empty()) return;
  const auto& samples = table.last_samples();
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const sim::ProbeSample& p = samples[i];
    std::printf("probe %s: u = (%.6g, %.6g, %.6g) m, von Mises %.6g Pa, pressure %.6g Pa\n",
                s.probes[i].name.c_str(), p.displacement[0], p.displacement[1], p.displacement[2],
                p.von_mises, p.pressure);
  }
  if (!table.last_reactions()) {
    if (!s.constraints.empty()) std::printf("reactions: not computed for this run\n");
    return;
  }
  const auto& reactions = *table.last_reactions();
  for (std::size_t c = 0; c < reactions.size(); ++c) {
    const Reaction& r = reactions[c];
    std::printf(
        "reaction of constraint %zu: F = (%.6g, %.6g, %.6g) N, M = (%.6g, %.6g, %.6g) N m "
        "about (%.4g, %.4g, %.4g) m\n",
        c, r.force[0], r.force[1], r.force[2], r.moment[0], r.moment[1], r.moment[2], r.point[0],
        r.point[1], r.point[2]);
  }
}

}  // namespace

void RunPrinter::print_summary(const sim::Simulation& simulation,
                               const std::filesystem::path& dir) {
  m_progress.finish();
  const scene::Scene& s = simulation.scene();
  if (const auto* tet = simulation.tet()) {
    const scene::TetSetup& setup = tet->setup();
    const tet::LinearSolver kind = setup.settings.linear_solver;
    const std::string iterations =
        kind != tet::LinearSolver::CHOLESKY
            ? ", " + std::to_string(m_total.cycles) + iteration_name(kind)
            : std::string();
    std::printf(
        "summary: %d vertices, %d tets, %zu Dirichlet vertices, %d frames, %d %s%s, worst "
        "relative residual %.2e\n"
        "time: setup %.2f s, rotate %.2f s, assemble %.2f s, solve %.2f s, output %.2f s\n",
        setup.mesh.vertex_count(), setup.mesh.tet_count(), setup.dirichlet_vertices.size(),
        m_frames, m_total.steps, s.time.quasistatic ? "static rounds" : "steps", iterations.c_str(),
        m_total.worst_residual, tet->setup_seconds(), m_total.rotate_seconds,
        m_total.assemble_seconds, m_total.solve_seconds, output_seconds());
    if (m_unconverged > 0)
      std::printf("warning: %d frame(s) did not converge (%s)\n", m_unconverged,
                  s.time.quasistatic ? "the static iteration or PCG did not reach tet.tolerance"
                                     : "PCG stopped at tet.max_iterations before tet.tolerance");
  } else {
    const sim::GridStepper& grid = *simulation.grid();
    const scene::GridSetup& setup = grid.setup();
    const auto& ph = grid.phase_seconds();
    const bool corotated = s.material_model == "corotated";
    std::printf(
        "summary: %zu interior + %zu Dirichlet cells (lattice %d x %d x %d, h = %.4g m), %d "
        "levels, %s%d frames, ",
        setup.interior_cells, setup.dirichlet_cells, setup.voxels.dims[0], setup.voxels.dims[1],
        setup.voxels.dims[2], setup.voxels.cell_size, grid.levels(),
        corotated ? "co-rotated model, " : "", m_frames);
    if (!s.time.quasistatic) {
      std::printf(
          "%d steps, %d %s%scycles, %sresidual reduction per cycle: mean %.3f, worst step %.3f",
          m_total.steps, m_total.cycles, corotated ? "" : s.cycle.c_str(), corotated ? "" : "-",
          corotated ? "non-linear " : "",
          m_rate_steps > 0 ? std::exp(m_log_rate_sum / m_rate_steps) : 0.0, m_total.worst_residual);
    } else {
      std::printf(
          "%d %s%scycles%s, worst relative %sresidual %.2e", m_total.cycles,
          corotated ? "" : s.cycle.c_str(), corotated ? "" : "-",
          s.accelerate && !corotated && s.precision != "single" ? " (FGMRES-accelerated)" : "",
          corotated ? "non-linear " : "", m_total.worst_residual);
    }
    if (corotated) std::printf(", last quasi-linear residual %.2e", m_last_quasi_linear);
    std::printf("\ntime: setup %.2f s, hierarchy %.2f s, solve %.2f s = %.3f s/frame",
                grid.setup_seconds(), grid.hierarchy_seconds(), m_total.solve_seconds,
                m_frames > 0 ? m_total.solve_seconds / m_frames : 0.0);
    // The co-rotated solvers do not time the linear hierarchy's phases.
    if (!corotated)
      std::printf(" (boundary %.2f, interior %.2f, residual %.2f, transfers %.2f, coarse %.2f)",
                  ph.boundary_smoothing, ph.interior_smoothing, ph.residual,
                  ph.restriction + ph.prolongation, ph.coarse_solve);
    std::printf(", output %.2f s\n", output_seconds());
    if (s.time.quasistatic && m_total.worst_residual > s.tolerance)
      std::printf("warning: some frames did not reach the tolerance %.1e: %s\n", s.tolerance,
                  unreached_tolerance_reason(s, m_stalled > 0).c_str());
  }
  print_probes(simulation.scene(), probes());
  std::printf("wrote %s\n", dir.string().c_str());
}

}  // namespace mgelastic::app
