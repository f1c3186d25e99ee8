#pragma once
// Baseline solver for benchmarks: hypre BoomerAMG-preconditioned CG on the same non-augmented
// system A u = c as the CG baseline (nonaugmented_system.hpp), with the systems options hypre
// recommends for elasticity: 3 functions (one per displacement component, given per unknown),
// HMIS coarsening, extended+i interpolation, strong threshold 0.5 in 3D, one V-cycle per PCG
// iteration. Available when mgelastic is configured with hypre (MGELASTIC_HAVE_HYPRE).
#include <Eigen/Sparse>
#include <vector>

namespace mgelastic::grid {

struct HypreReport {
  bool available = false;
  int iterations = 0;
  double setup_seconds = 0, solve_seconds = 0;
  double relative_residual = 0;
  bool converged = false;
};

// `component[i]` is the displacement component (0..2) of unknown i.
HypreReport boomeramg_pcg(const Eigen::SparseMatrix<double, Eigen::RowMajor>& a,
                          const Eigen::VectorXd& rhs, const std::vector<int>& component,
                          int dimension, double relative_tolerance, int max_iterations,
                          Eigen::VectorXd& solution);

}  // namespace mgelastic::grid
