#pragma once
// Tet-engine state of a Simulation ("engine": "tet"): corotated linear tetrahedra (Georgii &
// Westermann 2008). Per frame k (time (k + 1) dt) either one static equilibrium at that time
// (quasistatic) or `time.substeps` implicit steps of dt / substeps (dynamic); keyframed regions
// move with the clock.
//
// Fields: positions() and velocities() are 3N, vertex-major (numpy shape (N, 3)), m and m/s;
// von_mises() per tet, Pa; surface_vertices() the embedded render surface, N_s x 3.
#include <memory>
#include <vector>

#include "mgelastic/io/checkpoint.hpp"
#include "mgelastic/io/surface_mesh_writers.hpp"
#include "mgelastic/scene/scene.hpp"
#include "mgelastic/scene/tet_setup.hpp"
#include "mgelastic/sim/frame_stats.hpp"
#include "mgelastic/tet/corotated_solver.hpp"

namespace mgelastic::sim {

class TetStepper {
 public:
  explicit TetStepper(const scene::Scene& scene);

  // Computes frame `frame`; a failing step throws Error naming the step, the phase and the
  // frame's residuals so far. `attempt_time` is the frame's time.
  FrameStats advance_frame(int frame, double& attempt_time);
  double time() const { return m_time; }

  // Checkpoint arrays ("tet.positions", ..., "tet.counters"), then `attachments`.
  void save(io::Checkpoint& c, const std::vector<io::NamedArray>& attachments) const;
  void restore(const io::Checkpoint& c);

  void set_region_pose(std::size_t region, const Eigen::Vector3d& translate,
                       const Eigen::Quaterniond& rotate);

  // The scene's loads (tractions, pressures, forces) changed: the vertex forces are recomputed
  // and act from the next step on.
  void loads_changed();

  const scene::TetSetup& setup() const { return m_setup; }
  const tet::CorotatedSolver& solver() const { return *m_solver; }
  const Eigen::VectorXd& positions() const { return m_solver->positions(); }
  const Eigen::VectorXd& velocities() const { return m_solver->velocities(); }
  Eigen::MatrixXd von_mises() const;             // tets x 1
  double von_mises_of(int element) const;        // of one tet, Pa
  double pressure(int element) const;            // -trace(sigma) / 3 of one tet, Pa
  io::SurfaceVertices surface_vertices() const;  // deformed embedded surface
  const io::SurfaceVertices& rest_surface() const { return m_surface_rest; }
  const io::SurfaceTriangles& triangles() const { return m_setup.surface.triangles; }
  double setup_seconds() const { return m_setup_seconds; }

 private:
  void apply_motion();
  const scene::Scene* m_scene;
  scene::TetSetup m_setup;
  std::unique_ptr<tet::CorotatedSolver> m_solver;
  std::vector<scene::KeyframedMotion> m_motions;  // per constraint region
  io::SurfaceVertices m_surface_rest;
  double m_setup_seconds = 0, m_time = 0;
};

}  // namespace mgelastic::sim
