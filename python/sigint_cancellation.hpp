#pragma once
// Ctrl-C during a solve (the GIL released): while a SigintCancellation lives, SIGINT requests
// cancellation (core/cancellation.hpp), so the solve stops at the next cycle, instead of only
// being recorded by Python's own handler until the frame ends. Installed on the main thread only
// (where Python delivers signals) and only over Python's handler: a SIGINT that is ignored or left
// to its default action stays so. The previous handler is back when the guard ends.
//
// deliver() hands a caught Ctrl-C to Python as if it had just arrived: Python's SIGINT handler
// runs (KeyboardInterrupt by default, or the user's handler) and an exception it raises is
// thrown as pybind11::error_already_set.
#include <csignal>

#include "mgelastic/core/cancellation.hpp"

namespace mgelastic::python {

class SigintCancellation {
 public:
  SigintCancellation();  // with the GIL held
  ~SigintCancellation();
  SigintCancellation(const SigintCancellation&) = delete;
  SigintCancellation& operator=(const SigintCancellation&) = delete;

  // True when a Ctrl-C arrived while the guard was installed.
  bool interrupted() const { return cancellation_requested(); }
  // With the GIL held.
  static void deliver();

 private:
  CancellationScope m_scope;  // arms Simulation::step's return to the frame's start
  bool m_installed = false;
  struct sigaction m_previous {};
};

}  // namespace mgelastic::python
