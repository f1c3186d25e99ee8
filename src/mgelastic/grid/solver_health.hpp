#pragma once
// Divergence detection and diagnosis for the grid multigrid solves.
//
// Detection (every cycle, free): the residual norm after each cycle, which the solve computes
// anyway, must be finite and stay below kResidualGrowthLimit times the solve's initial residual.
// Diagnosis (only after a detection): the solve restores its starting unknowns and replays its
// cycles with a CycleMonitor attached. The cycle then stops after every phase on every level to
// recompute that level's residual norm ||b - L x|| and to check its unknowns for NaN/Inf. The
// report names the first phase that produced non-finite values or, when all stay finite, the
// phase that grew its level's residual the most, with the residual history. The replay repeats
// the failing solve exactly (the kernels are deterministic for a fixed thread count).
#include <limits>
#include <string>
#include <vector>

namespace mgelastic::grid {

inline constexpr double kResidualGrowthLimit = 1e4;

// Phases of one visit of level l in Multigrid::correct, in order. RESTRICTION is recorded on the
// coarse level (its residual right after restriction is its new right-hand side, x = 0).
enum class CyclePhase {
  CYCLE_START,                    // level 0 before the cycle (its right-hand side in float)
  PRE_SMOOTHING_BOUNDARY,         // band Gauss-Seidel before the distributive sweep
  PRE_SMOOTHING_INTERIOR,         // distributive sweep
  PRE_SMOOTHING_BOUNDARY_AFTER,   // band Gauss-Seidel after it + traction back-substitution
  RELOCATION_BEFORE_RESTRICTION,  // band sweeps over relocated-boundary rows
  RESTRICTION,                    // residual restricted to the coarse level
  COARSE_SOLVE,                   // direct solve of the coarsest level
  PROLONGATION,                   // coarse correction added to level l
  RELOCATION_AFTER_PROLONGATION,  // band sweeps over relocated-boundary rows
  POST_SMOOTHING_BOUNDARY,
  POST_SMOOTHING_INTERIOR,
  POST_SMOOTHING_BOUNDARY_AFTER,
};

const char* phase_name(CyclePhase phase);

// "a b c" with %.3e numbers.
std::string format_history(const std::vector<double>& residuals);

// Why a residual history shows divergence ("" when it does not): its last entry is non-finite or
// above kResidualGrowthLimit times its first.
std::string divergence_reason(const std::vector<double>& residuals);

// Stall detection of plain cycles (Multigrid::solve's stall_cycles): a cycle makes progress when
// its residual is below every residual after an earlier cycle. The initial residual does not
// count: a zero start's first cycle may raise the residual many times over (the armadillo at 128
// cells: x14, then 0.56 per cycle), and measuring progress against it stopped single-precision
// solves after three cycles at 5.8 times the initial residual, "stalled at float round-off".
class StallWatch {
 public:
  explicit StallWatch(int stall_cycles) : m_stall_cycles(stall_cycles) {}
  // Records the residual after a cycle; true once stall_cycles cycles in a row made no progress.
  bool stalled_after(double residual);

 private:
  int m_stall_cycles;
  int m_without_progress = 0;
  double m_smallest = std::numeric_limits<double>::infinity();
};

class CycleMonitor {
 public:
  struct Record {
    int cycle = 0;
    int level = 0;
    CyclePhase phase = CyclePhase::CYCLE_START;
    double residual = 0.0;        // the level's residual norm after the phase
    bool unknowns_finite = true;  // the level's x has no NaN/Inf
    bool finite() const;          // unknowns and residual
  };

  void start_cycle(int cycle) { m_cycle = cycle; }
  void record(int level, CyclePhase phase, double residual, bool unknowns_finite);
  // Stop replaying: a phase produced non-finite values.
  bool found_non_finite() const { return m_first_non_finite >= 0; }
  // The finding, e.g. "cycle 3, level 1 of 4, pre-smoothing (interior distributive sweep) first
  // produced non-finite values (level residual before it 2.1e+01)".
  std::string diagnosis(int levels) const;
  const std::vector<Record>& records() const { return m_records; }

 private:
  int m_cycle = 0;
  int m_first_non_finite = -1;
  std::vector<Record> m_records;
};

}  // namespace mgelastic::grid
