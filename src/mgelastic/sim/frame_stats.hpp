#pragma once
// Solver statistics of one frame of a Simulation, for both engines.
#include <vector>

namespace mgelastic::sim {

// One solve: a backward-Euler / implicit step (dynamic), or the frame's equilibrium solve
// (quasistatic).
struct StepStats {
  int cycles = 0;                     // grid: multigrid cycles; tet: linear solver iterations
  double relative_residual = 0;       // last / first residual (grid co-rotated: the non-linear one)
  double quasi_linear_reduction = 0;  // grid co-rotated: last / first of the frozen system
  double quasi_linear_residual = 0;   // grid co-rotated: last residual of the frozen system
  bool converged = true;
  // Grid: stopped short of the tolerance where round-off stalled the residual (single precision:
  // float round-off; mixed and double precision: the round-off floor of x in double,
  // ~eps |A| |x|); relative_residual is the level reached.
  bool stalled = false;
  double seconds = 0;
};

struct FrameStats {
  int frame = -1;   // index; the frame shows the state at `time`
  double time = 0;  // s
  int steps = 0;    // time steps (dynamic), static rounds (tet quasistatic), 1 (grid quasistatic)
  int cycles = 0;   // summed over the steps
  double worst_residual = 0;  // worst relative residual of the steps
  bool converged = true;
  double solve_seconds = 0;  // wall time of the steps (grid: the whole step, not only its cycles)
  double rotate_seconds = 0, assemble_seconds = 0;  // tet engine phases
  std::vector<StepStats> step_stats;                // each step (tet quasistatic: the last round)
};

}  // namespace mgelastic::sim
