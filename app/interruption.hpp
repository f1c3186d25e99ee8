#pragma once
// Ctrl-C (SIGINT) and SIGTERM during `mgelastic run`: the handler records the request and
// requests cancellation (core/cancellation.hpp), so the solve in progress stops at its next
// cycle and the simulation returns to its last completed frame (or, when the frame's solves were
// done, the frame is finished and written); the run writes the checkpoint of that frame,
// reports, and stops; the CLI then exits with 130. A second signal is not caught, so a stuck run
// can still be killed.
namespace mgelastic::app {

// Installs the handlers for the lifetime of the object (one run).
class InterruptionGuard {
 public:
  InterruptionGuard();
  ~InterruptionGuard();
  InterruptionGuard(const InterruptionGuard&) = delete;
  InterruptionGuard& operator=(const InterruptionGuard&) = delete;
};

bool interruption_requested();

}  // namespace mgelastic::app
