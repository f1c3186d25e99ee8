#pragma once
// Baseline of the paper's Fig. 11: unpreconditioned conjugate gradients on the non-augmented
// staggered system A u = c (A = -S, see nonaugmented_system.hpp), recording the residual
// history ||c - A u||_2 per iteration.
#include <Eigen/Sparse>
#include <vector>

namespace mgelastic::grid {

struct CgReport {
  std::vector<double> residuals;  // before the first iteration, then after each
  int iterations = 0;
  double seconds = 0;
  bool converged = false;
};

CgReport conjugate_gradient(const Eigen::SparseMatrix<double, Eigen::RowMajor>& a,
                            const Eigen::VectorXd& rhs, Eigen::VectorXd& x,
                            double relative_tolerance, int max_iterations);

}  // namespace mgelastic::grid
