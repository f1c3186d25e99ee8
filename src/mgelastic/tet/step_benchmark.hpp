#pragma once
// The Table 1/2 benchmark of Georgii & Westermann 2008 on generated meshes: per implicit Euler
// step of a corotated bar, seconds for rotate, assemble, the Galerkin update of the multigrid
// hierarchy (naive Eq. 9 and stream Algorithm 1), the solve (one V-cycle, MG-PCG, and the existing
// block-Jacobi PCG as baseline), and steps per second.
//
// Problem: bar 1 x 0.25 x 0.25 m, `cells_across` cubes across (24 n^3 Kuhn tets), E = 1e6 Pa,
// nu = 0.3, rho = 1000, h = 1/60 s, gravity, left end fixed, right end turned about the bar axis at
// 6 rad/s, energy-minimization rotations. Each step is taken by CorotatedSolver (rotations,
// assembly, baseline PCG to `tolerance`); the multigrid then updates from that step's K~ and
// solves the step matrix with a seeded random right-hand side (zero on Dirichlet vertices) to the
// same tolerance. Times are means over `steps` steps after one warm-up step.
#include <cstddef>
#include <vector>

namespace mgelastic::tet {

struct TetStepBenchmark {
  int cells_across = 0, tets = 0, vertices = 0, levels = 0, threads = 1;
  std::vector<int> level_vertices;
  double setup_seconds = 0.0;  // hierarchy, coarse patterns, streams (once)
  double rotate_seconds = 0.0, assemble_seconds = 0.0;
  double fine_operator_seconds = 0.0;  // A_0 = M + h^2 K~ copied into the multigrid
  double galerkin_naive_seconds = 0.0, galerkin_stream_seconds = 0.0;
  double factor_seconds = 0.0;  // coarsest CHOLMOD factorization and smoother diagonals
  double vcycle_seconds = 0.0, mg_pcg_seconds = 0.0, baseline_pcg_seconds = 0.0;
  double mg_pcg_iterations = 0.0, baseline_pcg_iterations = 0.0;
  double vcycle_rate = 0.0;  // residual reduction per V-cycle (cycles 4..10)
  std::size_t stream_bytes = 0;
  // rotate + assemble + fine operator + stream update + factor + MG-PCG; and with the baseline.
  double mg_steps_per_second = 0.0, baseline_steps_per_second = 0.0;
};

// `max_coarsest_vertices`: TetHierarchySettings::max_coarsest_vertices.
TetStepBenchmark run_tet_step_benchmark(int cells_across, int steps, double tolerance,
                                        int max_coarsest_vertices = 2000);

}  // namespace mgelastic::tet
