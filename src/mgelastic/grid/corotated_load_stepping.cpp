// Load stepping (continuation) for quasistatic co-rotated solves. A cold start at an extreme
// load fails because the first cycle (R = I) returns the linear solution, which can bend a
// slender body past its length: its rotations are meaningless and the outer iteration diverges
// (docs/grid-engine.md). Ramping the load keeps every increment's start close to its solution,
// where the frozen-rotation iteration contracts.
#include <algorithm>
#include <cmath>
#include <string>

#include "mgelastic/core/cancellation.hpp"
#include "mgelastic/core/error.hpp"
#include "mgelastic/core/timer.hpp"
#include "mgelastic/grid/corotated_acceleration.hpp"
#include "mgelastic/grid/corotated_multigrid.hpp"

namespace mgelastic::grid {
namespace {

// Increments before the last need only a start for the next one.
constexpr double kIncrementTolerance = 0.1;

}  // namespace

template <int Dim>
typename CorotatedMultigrid<Dim>::Load CorotatedMultigrid<Dim>::current_load() const {
  const auto& finest = m_multigrid.level(0);
  Load load;
  load.b = finest.b;
  load.dirichlet.reserve(m_dirichlet.size());
  for (const std::uint32_t v : m_dirichlet) load.dirichlet.push_back(finest.at(v));
  load.traction = m_traction_scale;
  return load;
}

template <int Dim>
void CorotatedMultigrid<Dim>::set_traction_scale(double scale) {
  m_traction_scale = scale;
  if (!m_sigma_full || scale == 1.0) {
    m_sigma = m_sigma_full;
    return;
  }
  m_sigma = [full = m_sigma_full, scale](int i, int j, const Vec<Dim>& x) {
    return scale * full(i, j, x);
  };
}

// (1 - s) from + s to (exactly `to` at s = 1); then tractions and rows follow the new load.
template <int Dim>
void CorotatedMultigrid<Dim>::apply_load(const Load& from, const Load& to, double s) {
  auto& finest = m_multigrid.level(0);
  const auto blend = [s](double a, double b) { return s == 1.0 ? b : a + s * (b - a); };
  for (int f = 0; f <= Dim; ++f)
    for (std::size_t k = 0; k < finest.size(); ++k)
      finest.b[f][k] = blend(from.b[f][k], to.b[f][k]);
  for (std::size_t i = 0; i < m_dirichlet.size(); ++i)
    finest.at(m_dirichlet[i]) = blend(from.dirichlet[i], to.dirichlet[i]);
  set_traction_scale(blend(from.traction, to.traction));
  back_substitute(0);
  refresh_rotations();
}

// Cycles on the current load until the non-linear residual is below target * reference, or it
// grew kIncrementGrowth-fold over its start (DIVERGED), or max_cycles passed (STALLED).
template <int Dim>
typename CorotatedMultigrid<Dim>::Attempt CorotatedMultigrid<Dim>::solve_increment(
    double initial, double target, int max_cycles, CorotatedReport& report) {
  AndersonMixing anderson(m_options.acceleration_depth);
  double residual = initial;
  for (int cycle = 0; cycle < max_cycles; ++cycle) {
    throw_if_cancelled();
    if (residual <= target) return Attempt::CONVERGED;
    if (m_options.outer == CorotatedOuter::NEWTON_KRYLOV) {
      const int directions = std::min(m_options.rotation_update_every, max_cycles - cycle);
      cycle += newton_krylov_step(directions, target, report) - 1;
      residual = report.nonlinear.back();
      if (!std::isfinite(residual) || residual > kIncrementGrowth * initial)
        return Attempt::DIVERGED;
      continue;
    }
    double quasi_linear = 0;
    if (m_options.acceleration_depth > 0) {
      residual = accelerated_cycle(anderson, residual, quasi_linear);
    } else {
      quasi_linear = solve_cycle();
      residual = nonlinear_residual();
    }
    report.nonlinear.push_back(residual);
    report.quasi_linear.push_back(quasi_linear);
    if (!std::isfinite(residual) || residual > kIncrementGrowth * initial) return Attempt::DIVERGED;
  }
  return residual <= target ? Attempt::CONVERGED : Attempt::STALLED;
}

// Adaptive continuation: the load parameter s runs from 0 (`from`) to 1 (`to`); a failed
// increment is undone and halved, an accepted one doubles the next (at most to the end).
template <int Dim>
CorotatedReport CorotatedMultigrid<Dim>::solve_with_load_steps(double relative_tolerance,
                                                               int max_cycles) {
  Timer timer;
  const Load to = current_load();
  const Load from = m_equilibrium;
  CorotatedReport report;
  report.nonlinear.push_back(nonlinear_residual());
  report.quasi_linear.push_back(quasi_linear_residual());
  report.load_increments = 0;
  const double full_initial = report.nonlinear.front();
  if (!std::isfinite(full_initial))
    throw Error("the initial co-rotated residual is not finite (NaN or Inf in loads or values)");
  auto accepted = m_multigrid.level(0).x;
  double s = 0, ds = 1;
  const double smallest = 1.0 / kMaxLoadIncrements;
  while (s < 1) {
    const double next = ds >= 1 - s ? 1.0 : s + ds;
    const bool last = next == 1.0;
    // The full load at once is solve() (no reload, no extra refresh).
    if (s > 0 || !last) apply_load(from, to, next);
    const double initial = s > 0 || !last ? nonlinear_residual() : full_initial;
    const double target = last ? relative_tolerance * full_initial
                               : std::max(relative_tolerance, kIncrementTolerance) * initial;
    const Attempt outcome = solve_increment(initial, target, max_cycles, report);
    if (outcome == Attempt::CONVERGED || (outcome == Attempt::STALLED && ds <= smallest)) {
      accepted = m_multigrid.level(0).x;
      s = next;
      ds *= 2;
      ++report.load_increments;
      report.converged = outcome == Attempt::CONVERGED;
      continue;
    }
    if (ds <= smallest)
      throw Error("co-rotated multigrid diverged: the non-linear residual grew " +
                  std::to_string(static_cast<int>(kIncrementGrowth)) +
                  "-fold within a load increment of 1/" + std::to_string(kMaxLoadIncrements) +
                  " of the load (at " + std::to_string(s) + " of it)");
    assign_live(m_multigrid.level(0).x, accepted, m_multigrid.level(0).live);
    ds /= 2;
  }
  report.seconds = timer.seconds();
  m_equilibrium = to;
  return report;
}

template CorotatedReport CorotatedMultigrid<2>::solve_with_load_steps(double, int);
template CorotatedReport CorotatedMultigrid<3>::solve_with_load_steps(double, int);
template CorotatedMultigrid<2>::Load CorotatedMultigrid<2>::current_load() const;
template CorotatedMultigrid<3>::Load CorotatedMultigrid<3>::current_load() const;

}  // namespace mgelastic::grid
