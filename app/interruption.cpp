#include "interruption.hpp"

#include <csignal>

#include "mgelastic/core/cancellation.hpp"

namespace mgelastic::app {
namespace {

volatile std::sig_atomic_t g_requested = 0;

extern "C" void record_request(int signal) {
  g_requested = 1;
  request_cancellation();        // the solve stops at its next cycle (inside a CancellationScope)
  std::signal(signal, SIG_DFL);  // the next one terminates
}

}  // namespace

InterruptionGuard::InterruptionGuard() {
  std::signal(SIGINT, record_request);
  std::signal(SIGTERM, record_request);
}

InterruptionGuard::~InterruptionGuard() {
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
}

bool interruption_requested() {
  return g_requested != 0;
}

}  // namespace mgelastic::app
