#pragma once
// The files of `mgelastic run`, written by an Observer after every frame (atomically, so an
// interrupted run leaves every finished frame readable), with the io/ writers:
//   grid  vtk: grid_NNNN.vti (displacement; cell_type, pressure, von_mises; Float32 for
//              single-precision solves) and surface_NNNN.vtp (deformed embedded surface)
//   tet   vtk: tet_NNNN.vtu (deformed mesh; displacement, von_mises) and surface_NNNN.vtp
//   both  obj/ply: surface_NNNN.obj / .ply (binary); simulation.pvd (the series so far);
//         probes.csv (probe_table.hpp) when the scene has probes or constraints;
//         checkpoint.mgck as scheduled by RunCheckpoints (run_checkpoints.hpp).
#include <filesystem>
#include <functional>
#include <vector>

#include "mgelastic/io/vtk_writers.hpp"
#include "mgelastic/sim/observer.hpp"
#include "mgelastic/sim/probe_table.hpp"
#include "mgelastic/sim/run_checkpoints.hpp"

namespace mgelastic::sim {

class OutputObserver : public Observer {
 public:
  // Continues the series of checkpoints.resume_from() when there is one.
  OutputObserver(const scene::Scene& scene, std::filesystem::path dir, RunCheckpoints& checkpoints);

  void started(const Simulation& simulation) override;
  // Writes the frame's files and the series, hands the state to the checkpoints; returns false
  // (after a checkpoint now) when `stop_requested` says so.
  bool frame_done(const Simulation& simulation, const FrameStats& stats) override;
  // Saves the last good state; the error says which frames are complete.
  Error frame_failed(const Simulation& simulation, const Error& error) override;

  std::function<bool()> stop_requested;
  double output_seconds() const { return m_output_seconds; }
  double last_output_seconds() const { return m_last_output_seconds; }
  const std::vector<io::SeriesEntry>& series() const { return m_series; }
  const ProbeTable& probes() const { return m_probes; }

 private:
  const scene::Scene* m_scene;
  std::filesystem::path m_dir;
  RunCheckpoints* m_checkpoints;
  std::vector<io::SeriesEntry> m_series;
  ProbeTable m_probes;
  double m_output_seconds = 0, m_last_output_seconds = 0;
};

// One frame's files of the simulation's current state; returns the frame's .pvd entries.
std::vector<io::SeriesEntry> write_frame(const Simulation& simulation,
                                         const std::filesystem::path& dir, int frame, double time);

}  // namespace mgelastic::sim
