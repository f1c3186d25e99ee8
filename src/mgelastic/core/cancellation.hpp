#pragma once
// Cooperative cancellation of long solves (Ctrl-C in Python, an application's stop button). One
// process-wide request flag: a signal handler, another thread or a callback sets it, and the
// solve loops (grid and tet multigrid, FGMRES, co-rotated Newton and load stepping, tet PCG)
// call throw_if_cancelled() once per cycle or iteration, so a request stops the computation
// within one cycle. The loops leave their state half-way: the caller returns to a saved state
// (sim::Simulation::step does so while a CancellationScope is alive).
//
// Cancelled is not an mgelastic::Error: the places that turn a solver's Error into a message of
// their own (a diverged time step, a failed frame) let it pass unchanged.
//
// Header-only: the flag is an inline variable (one object in the program), and the checks inline
// to a relaxed load and increment per cycle.
#include <atomic>
#include <cstdint>
#include <stdexcept>

namespace mgelastic {

namespace cancellation_detail {
inline std::atomic<bool> requested{false};
inline std::atomic<int> scopes{0};
inline std::atomic<std::uint64_t> checks{0};
inline constexpr std::uint64_t kNever = ~std::uint64_t{0};
inline std::atomic<std::uint64_t> request_at_check{kNever};
// A signal handler may store to the flag only if that cannot take a lock.
static_assert(std::atomic<bool>::is_always_lock_free);
}  // namespace cancellation_detail

class Cancelled : public std::runtime_error {
 public:
  Cancelled() : std::runtime_error("cancelled") {}
};

// Sets the request; async-signal-safe (a lock-free atomic store), so a SIGINT handler may call
// it.
inline void request_cancellation() noexcept {
  cancellation_detail::requested.store(true, std::memory_order_relaxed);
}
inline bool cancellation_requested() noexcept {
  return cancellation_detail::requested.load(std::memory_order_relaxed);
}
// Throws Cancelled when a request is pending (the request stays until a scope clears it).
inline void throw_if_cancelled() {
  using namespace cancellation_detail;
  const std::uint64_t check = checks.fetch_add(1, std::memory_order_relaxed) + 1;
  if (check == request_at_check.load(std::memory_order_relaxed)) request_cancellation();
  if (cancellation_requested()) throw Cancelled();
}
// Calls of throw_if_cancelled() so far in this process: tests and bindings compare the cycles a
// cancelled solve ran with those of a whole one.
inline std::uint64_t cancellation_checks() noexcept {
  return cancellation_detail::checks.load(std::memory_order_relaxed);
}

// Requests cancellation when the n-th check from now runs (n >= 1): a deterministic request at a
// chosen cycle, for tests and for a budget of cycles. A scope's start or end cancels it.
inline void request_cancellation_at_check(std::uint64_t n) noexcept {
  cancellation_detail::request_at_check.store(cancellation_checks() + n, std::memory_order_relaxed);
}

// The time a computation may be cancelled: clears any earlier request on entry and on exit. With
// `return_to_start` (the default), cancellation_armed() is true while it lives: Simulation::step
// then keeps a copy of the frame's start state (about 56 bytes per grid cell) to return to. A
// program that stops for good after a cancel (the CLI: its checkpoint already holds the last
// frame) passes false and saves the copy. Scopes may nest; the request flag is shared by all.
class CancellationScope {
 public:
  explicit CancellationScope(bool return_to_start = true) noexcept : m_arms(return_to_start) {
    cancellation_detail::request_at_check.store(cancellation_detail::kNever);
    cancellation_detail::requested.store(false, std::memory_order_relaxed);
    if (m_arms) cancellation_detail::scopes.fetch_add(1, std::memory_order_relaxed);
  }
  ~CancellationScope() {
    if (m_arms) cancellation_detail::scopes.fetch_sub(1, std::memory_order_relaxed);
    cancellation_detail::request_at_check.store(cancellation_detail::kNever);
    cancellation_detail::requested.store(false, std::memory_order_relaxed);
  }
  CancellationScope(const CancellationScope&) = delete;
  CancellationScope& operator=(const CancellationScope&) = delete;

 private:
  bool m_arms;
};
inline bool cancellation_armed() noexcept {
  return cancellation_detail::scopes.load(std::memory_order_relaxed) > 0;
}

}  // namespace mgelastic
