#pragma once
// What `mgelastic run` prints around a sim::Simulation: the scene and hierarchy before the
// frames, a progress line (grid) or one line (tet) per frame, and a summary with phase times.
// The files are written by sim::OutputObserver, which this observer extends.
#include "mgelastic/sim/output_observer.hpp"
#include "mgelastic/sim/simulation.hpp"
#include "progress.hpp"

namespace mgelastic::app {

// Scene, setup and hierarchy lines of a freshly built simulation.
void print_setup(const sim::Simulation& simulation, double build_seconds);

class RunPrinter : public sim::OutputObserver {
 public:
  RunPrinter(const scene::Scene& scene, std::filesystem::path dir,
             sim::RunCheckpoints& checkpoints);
  bool frame_done(const sim::Simulation& simulation, const sim::FrameStats& stats) override;
  Error frame_failed(const sim::Simulation& simulation, const Error& error) override;
  // Ctrl-C stopped a frame between two solver cycles (core/cancellation.hpp): the checkpoint file
  // is made to hold the last completed frame (the simulation's own state is half-way).
  void cancelled(const sim::Simulation& simulation, sim::RunCheckpoints& checkpoints);
  // The summary lines after the run.
  void print_summary(const sim::Simulation& simulation, const std::filesystem::path& dir);

 private:
  Progress m_progress;
  sim::FrameStats m_total;  // summed over the frames of this run
  int m_frames = 0, m_unconverged = 0, m_rate_steps = 0;
  int m_stalled = 0;  // grid steps stopped at the round-off floor of their precision
  double m_log_rate_sum = 0, m_last_quasi_linear = 0;
};

}  // namespace mgelastic::app
