#pragma once
// Grid-engine state of a Simulation: the scene's lattice problem and one of four solvers, chosen
// by two settings: the model (`material.model`: linear multigrid, Sec. 5-6, or co-rotated,
// Sec. 7) and the integrator (`time.quasistatic`: one equilibrium per frame at time (k + 1) dt,
// or `time.substeps` backward-Euler steps per frame, Sec. 8). One frame loop drives all four.
//
// Fields (computed on first access after each frame, then cached), all x fastest:
//   displacement()  nodal, (nx + 1)(ny + 1)(nz + 1) nodes x 3 components, m
//   velocity()      nodal, same layout, m/s (zero for quasistatic runs)
//   pressure()      per lattice cell, nx ny nz, -trace(sigma) / 3 in Pa (0 outside interior
//                   cells)
//   von_mises()     per lattice cell, Pa (0 in exterior cells)
//   cell_types()    per lattice cell, grid::CellType values
// In numpy terms a nodal field is a C-order array of shape (nz + 1, ny + 1, nx + 1, 3), or with
// strides the (nx + 1, ny + 1, nz + 1, 3) view.
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "mgelastic/grid/multigrid.hpp"
#include "mgelastic/grid/node_fields.hpp"
#include "mgelastic/grid/surface_interpolation.hpp"
#include "mgelastic/io/checkpoint.hpp"
#include "mgelastic/scene/grid_setup.hpp"
#include "mgelastic/scene/scene.hpp"
#include "mgelastic/sim/frame_stats.hpp"

namespace mgelastic::sim {

class GridStepper {
 public:
  // Builds the lattice problem and the solver hierarchy; throws Error for unsupported settings.
  explicit GridStepper(const scene::Scene& scene);
  ~GridStepper();
  GridStepper(const GridStepper&) = delete;
  GridStepper& operator=(const GridStepper&) = delete;

  // Computes frame `frame`; `attempt_time` is set to the time of the solve in progress (for
  // failure messages).
  FrameStats advance_frame(int frame, double& attempt_time);
  // Clock of the last completed frame (dynamic: the integrator's clock).
  double time() const;

  // Checkpoint arrays: the finest unknowns ("grid.x0".."grid.x3"), then `attachments`, then the
  // carried state of the model/integrator (velocities "grid.v*", co-rotated state).
  void save(io::Checkpoint& c, const std::vector<io::NamedArray>& attachments) const;
  void restore(const io::Checkpoint& c);
  // The start of the next frame, to return to after a cancelled step (core/cancellation.hpp):
  // save()'s arrays and the solution level's right-hand side, which a cancelled solve may leave
  // half-way (a co-rotated load increment's blend). Loads changed since the last step go into
  // the solver first. return_to_start restores it without a
  // hierarchy build (co-rotated: its rows from the carried rotations, as restore() does); the
  // continuation is then that of a resumed checkpoint.
  void save_start(io::Checkpoint& start);
  void return_to_start(const io::Checkpoint& start);

  // Keyframed region `region` (index in the scene's constraints) holds this rigid pose (about
  // its pivot) from now on.
  void set_region_pose(std::size_t region, const Eigen::Vector3d& translate,
                       const Eigen::Quaterniond& rotate);

  // The scene's loads (tractions, pressures, forces) changed: the next step applies them. Every
  // model replaces the loads in its hierarchy (boundary values, right-hand side, the co-rotated
  // rows' constants; Multigrid::set_loads, CorotatedMultigrid::set_loads), no rebuild; the
  // state (unknowns, co-rotated state, velocities) stays, as a checkpoint would carry it.
  void loads_changed() { m_loads_changed = true; }

  const scene::GridSetup& setup() const { return m_setup; }
  bool single_precision() const;
  const grid::NodeDisplacement& displacement() const;
  const std::vector<double>& velocity() const;
  const std::vector<double>& pressure() const;
  const std::vector<double>& von_mises() const;
  const std::vector<std::uint8_t>& cell_types() const;
  const grid::PointRows& surface_vertices() const;  // deformed embedded surface, N x 3
  const geometry::TriangleMesh& rest_surface() const { return m_setup.surface; }
  // The linear model's finest level in double (its x: the solution), for reactions; null for
  // the co-rotated model.
  const grid::Level<3, double>* linear_solution() const;
  // The co-rotated model's finest level (its x: the solution), for reactions; null for the
  // linear model.
  const grid::Level<3, double>* corotated_solution() const;
  Eigen::Vector3i cells() const;  // lattice cells per axis
  double spacing() const;
  Eigen::Vector3d origin() const;

  // For reports: hierarchy size and phase times, the model's description.
  int levels() const;
  std::size_t unknowns() const;
  std::size_t bytes() const;  // 0 where not measured (co-rotated)
  const grid::PhaseSeconds& phase_seconds() const;
  double hierarchy_seconds() const { return m_hierarchy_seconds; }
  double setup_seconds() const { return m_setup_seconds; }
  // Seconds the last load change took (the loads replaced in the solver).
  double load_update_seconds() const { return m_load_update_seconds; }
  double inertia() const;  // backward Euler c (N/m^4), 0 quasistatic
  double step_dt() const { return m_step_dt; }

  class Solver;  // one of the four model x integrator combinations

 private:
  void invalidate();
  void reload_loads();
  const scene::Scene* m_scene;
  scene::GridSetup m_setup;
  std::unique_ptr<Solver> m_solver;
  double m_setup_seconds = 0, m_hierarchy_seconds = 0, m_step_dt = 0, m_time = 0;
  double m_load_update_seconds = 0;
  bool m_loads_changed = false;
  struct Cache;
  std::unique_ptr<Cache> m_cache;
};

}  // namespace mgelastic::sim
