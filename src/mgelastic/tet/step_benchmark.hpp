#pragma once
// The Table 1/2 benchmark of Georgii & Westermann 2008: per implicit Euler step of a corotated
// body, seconds for rotate, assemble, the Galerkin update of the multigrid hierarchy (naive Eq. 9
// and stream Algorithm 1), the solve (the paper's fixed V-cycles), the whole step, steps per
// second; with the project's block-Jacobi PCG and MG-PCG as baselines on the same step matrix.
//
// Problems:
//  * bar (mesh_file empty): 1 x 0.25 x 0.25 m, `cells_across` cubes across (24 n^3 Kuhn tets),
//    E = 1e6 Pa, left end fixed, right end turned about the bar axis at 6 rad/s;
//  * a tetrahedral mesh file (read_tet_mesh), refined `refinements` times (refine_uniform), E =
//    1e4 Pa x its height, the lowest 10 % of its height fixed (it sags under gravity).
// Both: nu = 0.3, rho = 1000, h = 1/60 s, gravity. Every step is CorotatedSolver::step() with
// LinearSolver::MULTIGRID and `vcycles` V-cycles from the previous velocity (the real step: its
// right-hand side, warm start, Galerkin update with the stream product). After each step the
// Galerkin update is repeated with the naive product (timed, then restored by the stream), and
// block-Jacobi PCG, MG-PCG and V-cycles solve the step matrix with a seeded random right-hand
// side (zero on Dirichlet vertices) from zero to `tolerance`. Times are means over `steps` steps
// after one warm-up step.
#include <Eigen/SparseCore>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "mgelastic/tet/rotation_field.hpp"
#include "mgelastic/tet/tet_multigrid.hpp"

namespace mgelastic::tet {

// An outside solver run on the last step matrix (e.g. hypre BoomerAMG-PCG, supplied by the app so
// that the tet module does not depend on hypre): A (3N x 3N, identity rows on Dirichlet vertices,
// unknowns vertex-major), the random right-hand side, the relative tolerance.
struct ExternalSolveResult {
  bool available = false;
  int iterations = 0;
  double setup_seconds = 0.0, solve_seconds = 0.0;
  bool converged = false;
};
using ExternalSolver = std::function<ExternalSolveResult(
    const Eigen::SparseMatrix<double, Eigen::RowMajor>&, const Eigen::VectorXd&, double)>;

struct TetStepBenchmarkOptions {
  int cells_across = 8;
  std::string mesh_file;  // non-empty: this mesh instead of the bar
  int refinements = 0;
  RotationMethod rotation = RotationMethod::ENERGY_MINIMIZATION;
  int steps = 5;
  int vcycles = 1;
  double tolerance = 1e-6;
  TetMultigridSettings multigrid;
  ExternalSolver external_solver;  // empty: none
  // Only the steps: no naive product, baseline solves or rate (for profiling the step alone).
  bool steps_only = false;
};

struct TetStepBenchmark {
  std::string mesh;  // "bar n" or the file name (+ refinements)
  int tets = 0, vertices = 0, levels = 0, threads = 1;
  std::vector<int> level_vertices;
  double setup_seconds = 0.0;  // hierarchy, coarse patterns, streams (first solve)
  double rotate_seconds = 0.0, assemble_seconds = 0.0;
  double fine_operator_seconds = 0.0;  // A_0 = M + h^2 K~ copied into the multigrid
  double galerkin_naive_seconds = 0.0, galerkin_stream_seconds = 0.0;
  double factor_seconds = 0.0;     // coarsest Cholesky and smoother diagonals
  double solve_seconds = 0.0;      // the step's V-cycles and residual
  double step_seconds = 0.0;       // CorotatedSolver::step() wall time (forces and update included)
  double step_cpu_seconds = 0.0;   // CPU time of the process over the step (all threads)
  double step_residual = 0.0;      // mean relative residual of the step after its V-cycles
  double newton_iterations = 0.0;  // energy minimization: mean Newton iterations per element
  double mg_pcg_seconds = 0.0, baseline_pcg_seconds = 0.0, vcycles_to_tolerance_seconds = 0.0;
  double mg_pcg_iterations = 0.0, baseline_pcg_iterations = 0.0, vcycles_to_tolerance = 0.0;
  double vcycle_rate = 0.0;  // residual reduction per V-cycle (cycles 4..10, random b)
  std::size_t stream_bytes = 0;
  ExternalSolveResult external;                              // on the last step's matrix
  int smoother_colors = 0, smoother_clustered_vertices = 0;  // level 0
  int feature_patches = 0, feature_patch_colors = 0;         // multigrid.patches (level 0)
  double steps_per_second = 0.0;                             // 1 / step_seconds
  double baseline_steps_per_second = 0.0;  // step with BJ-PCG instead of Galerkin + V-cycles
};

TetStepBenchmark run_tet_step_benchmark(const TetStepBenchmarkOptions& options);

}  // namespace mgelastic::tet
