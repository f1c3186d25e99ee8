#include "sigint_cancellation.hpp"

#include <pybind11/pybind11.h>

namespace py = pybind11;

namespace mgelastic::python {
namespace {

extern "C" void request_on_sigint(int) {
  request_cancellation();
}

bool on_main_thread() {
  const py::module_ threading = py::module_::import("threading");
  return threading.attr("current_thread")().is(threading.attr("main_thread")());
}

}  // namespace

SigintCancellation::SigintCancellation() {
  if (!on_main_thread()) return;
  struct sigaction current {};
  if (sigaction(SIGINT, nullptr, &current) != 0) return;
  const bool plain = !(current.sa_flags & SA_SIGINFO);
  if (plain && (current.sa_handler == SIG_IGN || current.sa_handler == SIG_DFL)) return;
  struct sigaction ours {};
  ours.sa_handler = request_on_sigint;
  sigemptyset(&ours.sa_mask);
  m_installed = sigaction(SIGINT, &ours, &m_previous) == 0;
}

SigintCancellation::~SigintCancellation() {
  if (m_installed) sigaction(SIGINT, &m_previous, nullptr);
}

void SigintCancellation::deliver() {
  PyErr_SetInterrupt();
  if (PyErr_CheckSignals() != 0) throw py::error_already_set();
}

}  // namespace mgelastic::python
