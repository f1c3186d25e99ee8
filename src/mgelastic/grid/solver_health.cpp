#include "mgelastic/grid/solver_health.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace mgelastic::grid {
namespace {

std::string number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3e", v);
  return buffer;
}

std::string where(const CycleMonitor::Record& r, int levels) {
  return "cycle " + std::to_string(r.cycle) + ", level " + std::to_string(r.level) + " of " +
         std::to_string(levels) + " (0 = finest), " + phase_name(r.phase);
}

}  // namespace

const char* phase_name(CyclePhase phase) {
  switch (phase) {
    case CyclePhase::CYCLE_START:
      return "cycle start (right-hand side of the correction)";
    case CyclePhase::PRE_SMOOTHING_BOUNDARY:
      return "pre-smoothing (boundary band sweeps)";
    case CyclePhase::PRE_SMOOTHING_INTERIOR:
      return "pre-smoothing (interior distributive sweep)";
    case CyclePhase::PRE_SMOOTHING_BOUNDARY_AFTER:
      return "pre-smoothing (boundary band sweeps after the interior sweep)";
    case CyclePhase::RELOCATION_BEFORE_RESTRICTION:
      return "relocated-boundary sweeps before restriction";
    case CyclePhase::RESTRICTION:
      return "restriction (residual to this level)";
    case CyclePhase::COARSE_SOLVE:
      return "coarse solve";
    case CyclePhase::PROLONGATION:
      return "prolongation (coarse correction added)";
    case CyclePhase::RELOCATION_AFTER_PROLONGATION:
      return "relocated-boundary sweeps after prolongation";
    case CyclePhase::POST_SMOOTHING_BOUNDARY:
      return "post-smoothing (boundary band sweeps)";
    case CyclePhase::POST_SMOOTHING_INTERIOR:
      return "post-smoothing (interior distributive sweep)";
    case CyclePhase::POST_SMOOTHING_BOUNDARY_AFTER:
      break;
  }
  return "post-smoothing (boundary band sweeps after the interior sweep)";
}

std::string format_history(const std::vector<double>& residuals) {
  std::string text;
  for (double r : residuals) {
    if (!text.empty()) text += ' ';
    text += number(r);
  }
  return text;
}

bool StallWatch::stalled_after(double residual) {
  m_without_progress = residual < m_smallest ? 0 : m_without_progress + 1;
  m_smallest = std::min(m_smallest, residual);
  return m_stall_cycles > 0 && m_without_progress >= m_stall_cycles;
}

std::string divergence_reason(const std::vector<double>& residuals) {
  if (residuals.empty()) return "";
  const double last = residuals.back();
  if (!std::isfinite(last)) return "the residual is not finite";
  if (last > kResidualGrowthLimit * residuals.front())
    return "the residual grew to " + number(last) + ", more than " + number(kResidualGrowthLimit) +
           " times the initial " + number(residuals.front());
  return "";
}

bool CycleMonitor::Record::finite() const {
  return unknowns_finite && std::isfinite(residual);
}

void CycleMonitor::record(int level, CyclePhase phase, double residual, bool unknowns_finite) {
  m_records.push_back({m_cycle, level, phase, residual, unknowns_finite});
  if (!m_records.back().finite() && m_first_non_finite < 0)
    m_first_non_finite = static_cast<int>(m_records.size()) - 1;
}

std::string CycleMonitor::diagnosis(int levels) const {
  // The residual of the same level before a record: the previous record of that level in the
  // same cycle (a level's first record in a cycle is its start or its restriction).
  const auto before = [&](int i) {
    for (int j = i - 1; j >= 0 && m_records[j].cycle == m_records[i].cycle; --j)
      if (m_records[j].level == m_records[i].level) return m_records[j].residual;
    return -1.0;
  };
  if (m_first_non_finite >= 0) {
    const Record& r = m_records[m_first_non_finite];
    const double b = before(m_first_non_finite);
    // Finite unknowns with a non-finite residual: the level's own operator coefficients or
    // right-hand side are broken (or the residual overflows), not the phase's update.
    const std::string what = r.unknowns_finite
                                 ? " is the first phase after which the level's residual is not "
                                   "finite while its unknowns are (non-finite operator "
                                   "coefficients or right-hand side, or overflow)"
                                 : " first produced non-finite values";
    return where(r, levels) + what +
           (b >= 0 ? " (level residual before it " + number(b) + ")" : std::string());
  }
  int worst = -1;
  double worst_ratio = 1.0;
  // In the failing (last replayed) cycle: growth compounds over cycles, each cycle's culprit is
  // the same phase.
  for (int i = 0; i < static_cast<int>(m_records.size()); ++i) {
    if (m_records[i].cycle != m_cycle) continue;
    const double b = before(i);
    if (b > 0 && m_records[i].residual / b > worst_ratio) {
      worst_ratio = m_records[i].residual / b;
      worst = i;
    }
  }
  if (worst < 0) return "the replay found no phase that made its level's residual grow";
  return where(m_records[worst], levels) +
         " grew its level's residual the most: " + number(before(worst)) + " -> " +
         number(m_records[worst].residual) + " (x " + number(worst_ratio) + ")";
}

}  // namespace mgelastic::grid
