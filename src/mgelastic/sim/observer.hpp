#pragma once
// What Simulation::run reports to: the start of the run, every completed frame, a failed frame.
#include "mgelastic/core/error.hpp"
#include "mgelastic/sim/frame_stats.hpp"

namespace mgelastic::sim {

class Simulation;

class Observer {
 public:
  virtual ~Observer() = default;
  // Before the first frame of run() (after a resume: the first frame still to compute).
  virtual void started(const Simulation&) {}
  // After frame `stats.frame` completed; returning false stops the run after it.
  virtual bool frame_done(const Simulation&, const FrameStats&) { return true; }
  // A frame failed with `error` (a diverged solve); the result is thrown out of run().
  virtual Error frame_failed(const Simulation&, const Error& error) { return error; }
};

}  // namespace mgelastic::sim
