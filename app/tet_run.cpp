#include "tet_run.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "frame_files.hpp"
#include "interruption.hpp"
#include "mgelastic/core/error.hpp"
#include "mgelastic/core/timer.hpp"
#include "mgelastic/geometry/tet_mesh_vtu.hpp"
#include "mgelastic/io/surface_mesh_writers.hpp"
#include "mgelastic/io/vtk_writers.hpp"
#include "mgelastic/scene/tet_setup.hpp"
#include "mgelastic/tet/corotated_solver.hpp"
#include "mgelastic/tet/embedded_surface.hpp"
#include "mgelastic/tet/polar_rotation.hpp"
#include "run_checkpoints.hpp"

namespace mgelastic::app {
namespace {

// Rotation/solve rounds of one quasistatic frame. The frozen-rotation iteration of solve_static
// converges linearly, slower the more the body is twisted (~0.97 per round for a bar stretched
// 2.5x and turned once), so the cap is generous.
constexpr int kStaticRounds = 300;

// Von Mises stress of the corotated linear stress per element: strain
// eps = sym(R^T F) - I with R the polar rotation of F at the output positions (independent of the
// rotation method the solver used), sigma = lambda tr(eps) I + 2 mu eps,
// von Mises = sqrt(3/2 dev(sigma):dev(sigma)).
Eigen::MatrixXd von_mises_stress(const tet::TetBody& body, const Eigen::VectorXd& positions) {
  Eigen::MatrixXd stress(body.element_count(), 1);
  for (int e = 0; e < body.element_count(); ++e) {
    const Eigen::Matrix3d f =
        tet::deformation_gradient(body.corners(e, positions), body.rest_edge_inverse(e));
    const Eigen::Matrix3d unrotated = tet::polar_rotation(f).transpose() * f;
    const Eigen::Matrix3d strain =
        0.5 * (unrotated + unrotated.transpose()) - Eigen::Matrix3d::Identity();
    const Eigen::Vector2d lame = tet::lame_parameters(body.materials()[e]);
    const Eigen::Matrix3d sigma =
        lame[0] * strain.trace() * Eigen::Matrix3d::Identity() + 2.0 * lame[1] * strain;
    const Eigen::Matrix3d deviator = sigma - sigma.trace() / 3.0 * Eigen::Matrix3d::Identity();
    stress(e, 0) = std::sqrt(1.5 * deviator.squaredNorm());
  }
  return stress;
}

// Writes one frame's files; returns its .pvd entries. `surface_rest` is the surface at rest.
std::vector<io::SeriesEntry> write_frame(const scene::Scene& s, const scene::TetSetup& setup,
                                         const tet::CorotatedSolver& solver,
                                         const io::SurfaceVertices& surface_rest,
                                         const std::filesystem::path& dir, int frame, double time) {
  std::vector<io::SeriesEntry> entries;
  const Eigen::MatrixX3d positions = solver.positions_matrix();
  const Eigen::MatrixX3d displacement = positions - setup.mesh.vertices;
  const io::SurfaceVertices surface_vertices =
      tet::embedded_positions(setup.surface, positions, setup.mesh.tets);
  const io::SurfaceTriangles& triangles = setup.surface.triangles;
  if (wants(s, "vtk")) {
    geometry::TetMesh deformed = setup.mesh;
    deformed.vertices = positions;
    const std::string name = frame_name("tet", frame, "vtu");
    const geometry::VtuField point_fields[] = {{"displacement", displacement}};
    const geometry::VtuField cell_fields[] = {
        {"von_mises", von_mises_stress(solver.body(), solver.positions())}};
    geometry::write_vtu(dir / name, deformed, point_fields, cell_fields, vtk_encoding(s));
    entries.push_back({time, name, 0});
    const std::string surface_name = frame_name("surface", frame, "vtp");
    io::DataArray surface_displacement{"displacement", 3, {}};
    const io::SurfaceVertices moved = surface_vertices - surface_rest;
    surface_displacement.values.assign(moved.data(), moved.data() + moved.size());
    io::write_vtp(dir / surface_name, surface_vertices, triangles, {surface_displacement},
                  vtk_encoding(s));
    entries.push_back({time, surface_name, 1});
  }
  if (wants(s, "obj"))
    io::write_obj(dir / frame_name("surface", frame, "obj"), surface_vertices, triangles);
  if (wants(s, "ply"))
    io::write_ply(dir / frame_name("surface", frame, "ply"), surface_vertices, triangles, true);
  return entries;
}

std::string format_values(const std::vector<double>& values) {
  std::string text;
  char number[32];
  for (double v : values) {
    std::snprintf(number, sizeof number, "%s%.3e", text.empty() ? "" : " ", v);
    text += number;
  }
  return text;
}

// Work of one frame: its steps (or static rounds) summed.
struct FrameStats {
  int steps = 0;
  int iterations = 0;
  double worst_residual = 0.0;
  bool converged = true;
  double rotate_seconds = 0.0, assemble_seconds = 0.0, solve_seconds = 0.0;
  std::vector<double> residuals;  // of each step (or the last static round)
  void add(const tet::StepStats& step) {
    residuals.push_back(step.solve.relative_residual);
    iterations += step.solve.iterations;
    worst_residual = std::max(worst_residual, step.solve.relative_residual);
    converged = converged && step.solve.converged;
    rotate_seconds += step.rotate_seconds;
    assemble_seconds += step.assemble_seconds;
    solve_seconds += step.solve_seconds + step.galerkin_seconds;  // multigrid: Galerkin update
  }
};

// Checkpoint state of the tet engine (run_checkpoints.hpp): CorotatedState as arrays
// ("tet.rotations" holds the quaternions' x, y, z, w per element) and the series.
io::Checkpoint tet_checkpoint(const RunCheckpoints& checkpoints, const tet::CorotatedSolver& solver,
                              int frame, double time, const std::vector<io::SeriesEntry>& series) {
  const tet::CorotatedState state = solver.state();
  io::Checkpoint c = checkpoints.begin(frame, time);
  const auto add = [&](const char* name, const Eigen::VectorXd& v) {
    c.add<double>(name, std::span(v.data(), static_cast<std::size_t>(v.size())));
  };
  add("tet.positions", state.positions);
  add("tet.velocities", state.velocities);
  add("tet.accelerations", state.accelerations);
  std::vector<double> rotations;
  for (const Eigen::Quaterniond& q : state.rotations)
    rotations.insert(rotations.end(), q.coeffs().data(), q.coeffs().data() + 4);
  c.add<double>("tet.rotations", rotations);
  const std::vector<double> clock{state.time};
  c.add<double>("tet.time", clock);
  const std::vector<std::int64_t> counters{state.have_acceleration ? 1 : 0, state.steps};
  c.add<std::int64_t>("tet.counters", counters);
  add_series(c, series);
  return c;
}

void restore_tet(const io::Checkpoint& c, tet::CorotatedSolver& solver,
                 std::vector<io::SeriesEntry>& series) {
  tet::CorotatedState state = solver.state();
  const auto get = [&](const char* name, Eigen::VectorXd& v) {
    const std::vector<double> values = c.get<double>(name, v.size());
    v = Eigen::Map<const Eigen::VectorXd>(values.data(), v.size());
  };
  get("tet.positions", state.positions);
  get("tet.velocities", state.velocities);
  get("tet.accelerations", state.accelerations);
  const std::vector<double> rotations =
      c.get<double>("tet.rotations", 4 * static_cast<std::int64_t>(state.rotations.size()));
  for (std::size_t e = 0; e < state.rotations.size(); ++e)
    state.rotations[e].coeffs() = Eigen::Map<const Eigen::Vector4d>(rotations.data() + 4 * e);
  state.time = c.get<double>("tet.time", 1)[0];
  const std::vector<std::int64_t> counters = c.get<std::int64_t>("tet.counters", 2);
  state.have_acceleration = counters[0] != 0;
  state.steps = counters[1];
  try {
    solver.restore(state);
  } catch (const Error& e) {
    throw Error("corrupted checkpoint: " + e.reason(), ErrorContext{.file = c.source});
  }
  series = series_of(c);
}

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

}  // namespace

void run_tet_scene(const scene::Scene& s, const std::filesystem::path& output_dir,
                   RunCheckpoints& checkpoints) {
  Timer timer;
  const scene::TetSetup setup = scene::build_tet_setup(s);
  tet::CorotatedSolver solver(setup.mesh, setup.materials, setup.settings);
  solver.set_dirichlet(setup.dirichlet_vertices, setup.motion);
  if (setup.surface_forces.size() > 0) solver.set_surface_forces(setup.surface_forces);
  const io::SurfaceVertices surface_rest =
      tet::embedded_positions(setup.surface, setup.mesh.vertices, setup.mesh.tets);
  const double setup_seconds = timer.seconds();
  std::error_code ec;
  std::filesystem::create_directories(output_dir, ec);
  if (ec)
    throw Error("cannot create the output directory: " + ec.message(),
                ErrorContext{.file = output_dir.string()});

  const tet::LinearSolver kind = setup.settings.linear_solver;
  const bool pcg = kind != tet::LinearSolver::CHOLESKY;  // iterative: iterations are reported
  const char* solver_name = kind == tet::LinearSolver::MULTIGRID ? "multigrid V-cycles"
                            : kind == tet::LinearSolver::MG_PCG  ? "multigrid-preconditioned CG"
                            : pcg                                ? "block-Jacobi PCG"
                                                                 : "sparse Cholesky";
  const char* iteration_name = kind == tet::LinearSolver::MULTIGRID ? " V-cycles"
                               : kind == tet::LinearSolver::MG_PCG  ? " MG-PCG iterations"
                                                                    : " PCG iterations";
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
  std::fflush(stdout);

  std::vector<io::SeriesEntry> series;
  if (const io::Checkpoint* resume = checkpoints.resume_from()) {
    restore_tet(*resume, solver, series);
    std::printf("resumed from %s: frame %d (t = %.6g s) done\n", resume->source.c_str(),
                resume->frame, resume->time);
  }
  FrameStats total;
  double output_seconds = 0.0;
  int unconverged_frames = 0, frames_run = 0;
  for (int frame = checkpoints.first_frame(); frame < s.time.frames; ++frame) {
    // Frame k shows the state at time (k + 1) dt, as in the grid engine.
    const double time = (frame + 1) * s.time.dt;
    FrameStats stats;
    try {
      if (s.time.quasistatic) {
        // The clock decides where the keyframed regions are; the previous equilibrium is the
        // start.
        solver.set_time(time);
        const tet::StepStats& step = solver.solve_static(kStaticRounds, s.tet.tolerance);
        stats.add(step);
        stats.steps = step.static_iterations;
        stats.converged = stats.converged && step.static_converged;
      } else {
        for (int k = 0; k < s.time.substeps; ++k) {
          stats.add(solver.step());
          ++stats.steps;
        }
      }
    } catch (const Error& e) {
      // Which step of the frame failed, and how the steps before it went.
      const std::string history = stats.residuals.empty()
                                      ? std::string()
                                      : ", after " + std::to_string(stats.steps) +
                                            " good step(s) with relative residuals " +
                                            format_values(stats.residuals);
      std::string where = e.context().pointer;
      where = (where.empty() ? "" : where + ": ") + e.reason();
      const std::string step = s.time.quasistatic ? std::string("static solve")
                                                  : "step " + std::to_string(solver.step_count());
      throw frame_failed(
          Error(where + " (" + step + history + ")", ErrorContext{.pointer = "tet solver"}),
          checkpoints, frame, time);
    }
    ++frames_run;
    unconverged_frames += stats.converged ? 0 : 1;
    total.steps += stats.steps;
    total.iterations += stats.iterations;
    total.worst_residual = std::max(total.worst_residual, stats.worst_residual);
    total.rotate_seconds += stats.rotate_seconds;
    total.assemble_seconds += stats.assemble_seconds;
    total.solve_seconds += stats.solve_seconds;

    timer.restart();
    for (const auto& entry : write_frame(s, setup, solver, surface_rest, output_dir, frame, time))
      series.push_back(entry);
    if (!series.empty()) io::write_pvd(output_dir / "simulation.pvd", series);
    const double frame_output_seconds = timer.seconds();
    output_seconds += frame_output_seconds;
    const std::string iterations =
        pcg ? "  " + std::to_string(stats.iterations) + iteration_name : std::string();
    std::printf(
        "frame %4d/%d  t = %.4f s  %d %s%s  residual %.2e%s  rotate %.3f s  assemble %.3f s  "
        "solve %.3f s  output %.3f s\n",
        frame + 1, s.time.frames, time, stats.steps, s.time.quasistatic ? "rounds" : "steps",
        iterations.c_str(), stats.worst_residual, stats.converged ? "" : " (NOT converged)",
        stats.rotate_seconds, stats.assemble_seconds, stats.solve_seconds, frame_output_seconds);
    std::fflush(stdout);
    const bool interrupted = interruption_requested();
    checkpoints.completed(tet_checkpoint(checkpoints, solver, frame, time, series), interrupted);
    if (interrupted) {
      std::printf("interrupted: stopped after frame %d of %d; every written frame is complete\n",
                  frame + 1, s.time.frames);
      break;
    }
  }
  const std::string iterations =
      pcg ? ", " + std::to_string(total.iterations) + iteration_name : std::string();
  std::printf(
      "summary: %d vertices, %d tets, %zu Dirichlet vertices, %d frames, %d %s%s, worst "
      "relative residual %.2e\n"
      "time: setup %.2f s, rotate %.2f s, assemble %.2f s, solve %.2f s, output %.2f s\n",
      setup.mesh.vertex_count(), setup.mesh.tet_count(), setup.dirichlet_vertices.size(),
      frames_run, total.steps, s.time.quasistatic ? "static rounds" : "steps", iterations.c_str(),
      total.worst_residual, setup_seconds, total.rotate_seconds, total.assemble_seconds,
      total.solve_seconds, output_seconds);
  if (unconverged_frames > 0)
    std::printf("warning: %d frame(s) did not converge (%s)\n", unconverged_frames,
                s.time.quasistatic ? "the static iteration or PCG did not reach tet.tolerance"
                                   : "PCG stopped at tet.max_iterations before tet.tolerance");
  std::printf("wrote %s\n", output_dir.string().c_str());
}

}  // namespace mgelastic::app
