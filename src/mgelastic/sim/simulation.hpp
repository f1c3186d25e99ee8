#pragma once
// A simulation of one scene, frames in, fields out: one type for the grid and the tet engine.
//
//   scene::Scene s = scene::load_scene("examples/scenes/cantilever_bar.json");
//   sim::Simulation simulation(s);
//   while (simulation.frame() < simulation.frames()) simulation.step();
//   const grid::NodeDisplacement& u = simulation.grid()->displacement();
//
// Frame k (0-based) shows the state at time (k + 1) dt (dynamic runs: after `substeps` steps).
// step() computes the next frame; advance_to(t) steps until time() >= t; run(observer) steps to
// the scene's last frame, reporting each frame (output_observer.hpp writes the files of
// `mgelastic run`). Between steps keyframed regions may be given a new pose. The state is saved
// to and restored from a checkpoint (io/checkpoint.hpp); a restored simulation continues bit for
// bit as the one that saved it (same thread count).
//
// Fields live in the engine's stepper (grid_stepper.hpp / tet_stepper.hpp: shapes, units, layout)
// as contiguous arrays, valid until the next step.
#include <filesystem>
#include <memory>
#include <vector>

#include "mgelastic/io/checkpoint.hpp"
#include "mgelastic/io/surface_mesh_writers.hpp"
#include "mgelastic/scene/scene.hpp"
#include "mgelastic/sim/frame_stats.hpp"
#include "mgelastic/sim/grid_stepper.hpp"
#include "mgelastic/sim/observer.hpp"
#include "mgelastic/sim/tet_stepper.hpp"

namespace mgelastic::sim {

class Simulation {
 public:
  // Builds the engine the scene names (a validated scene, scene::load_scene / parse_scene).
  explicit Simulation(scene::Scene scene);
  // A simulation of `scene` continuing from the checkpoint file `path` (written by save() or a
  // run of the same scene with the same thread count; otherwise Error says why).
  static Simulation resume(scene::Scene scene, const std::filesystem::path& path);
  Simulation(Simulation&&) noexcept;
  Simulation& operator=(Simulation&&) noexcept;
  ~Simulation();

  const scene::Scene& scene() const;
  bool is_grid() const { return grid() != nullptr; }
  int frame() const;                // frames completed = index of the next frame
  int frames() const;               // the scene's time.frames
  double time() const;              // of the last completed frame; 0 before the first
  const FrameStats& stats() const;  // of the last completed frame

  // Computes the next frame. Cancelled (core/cancellation.hpp) stops it between two solver
  // cycles; while a CancellationScope is alive the simulation is then back at the last completed
  // frame, state and stats, as if the step had not run (the next step gives the same frame).
  const FrameStats& step();
  void advance_to(double time);
  // Steps until frames() or until `observer` stops the run; a failing frame throws
  // observer.frame_failed(...).
  void run(Observer& observer);
  // Time of the solve in progress or that failed last (for messages).
  double attempt_time() const;

  // Region `region` (index into the scene's constraints) holds the rigid pose x = R (X - pivot)
  // + pivot + translate from the next step on, replacing its keyframes.
  void set_region_pose(std::size_t region, const Eigen::Vector3d& translate,
                       const Eigen::Quaterniond& rotate);

  // Surface load `index` of the scene's loads.tractions / loads.pressures / loads.forces takes
  // this value from the next step on (a moving load): traction Pa, pressure Pa along the inward
  // rest normal, total force N; the selected surface stays that of the scene. scene() shows the
  // new value; its document (and so a checkpoint's scene fingerprint) keeps the file's. Error
  // naming /loads/<kind> when the scene has no such load or the value is not finite. Grid engine:
  // the next step first replaces the loads in the solver hierarchy (no rebuild),
  // GridStepper::loads_changed.
  void set_traction(std::size_t index, const Eigen::Vector3d& traction);
  void set_pressure(std::size_t index, double pressure);
  void set_force(std::size_t index, const Eigen::Vector3d& force);

  // The engine's state and fields; null for the other engine.
  const GridStepper* grid() const;
  const TetStepper* tet() const;

  // The deformed render surface (N x 3) and its triangles.
  io::SurfaceVertices surface_vertices() const;
  const io::SurfaceTriangles& surface_triangles() const;

  // Checkpoint of the last completed frame; `attachments` (e.g. the output series) are stored
  // among the engine's arrays at the place format version 1 files have them. `storage`: the
  // arrays of an older checkpoint, whose memory the new one reuses (a snapshot every frame).
  io::Checkpoint checkpoint(const std::vector<io::NamedArray>& attachments = {},
                            std::vector<io::NamedArray> storage = {}) const;
  void restore(const io::Checkpoint& checkpoint);
  void save(const std::filesystem::path& path) const;

 private:
  struct State;
  std::unique_ptr<State> m;
  void loads_changed();
};

}  // namespace mgelastic::sim
