#pragma once
// Ctrl-C (SIGINT) and SIGTERM during `mgelastic run`: the handler only records the request; the
// frame loops finish the frame in progress, write it and the series, report, and stop; the CLI
// then exits with 130. A second signal is not caught, so a stuck run can still be killed.
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
