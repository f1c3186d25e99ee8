#include "mgelastic/grid/cg_baseline.hpp"

#include <cmath>

#include "mgelastic/core/timer.hpp"

namespace mgelastic::grid {

CgReport conjugate_gradient(const Eigen::SparseMatrix<double, Eigen::RowMajor>& a,
                            const Eigen::VectorXd& rhs, Eigen::VectorXd& x,
                            double relative_tolerance, int max_iterations) {
  CgReport report;
  Timer timer;
  Eigen::VectorXd r = rhs - a * x;
  Eigen::VectorXd d = r;
  Eigen::VectorXd q(x.size());
  double rr = r.squaredNorm();
  report.residuals.push_back(std::sqrt(rr));
  const double target = relative_tolerance * report.residuals.front();
  while (report.iterations < max_iterations && std::sqrt(rr) > target) {
    q.noalias() = a * d;
    const double alpha = rr / d.dot(q);
    x += alpha * d;
    r -= alpha * q;
    const double rr_next = r.squaredNorm();
    d = r + (rr_next / rr) * d;
    rr = rr_next;
    ++report.iterations;
    report.residuals.push_back(std::sqrt(rr));
  }
  report.converged = std::sqrt(rr) <= target;
  report.seconds = timer.seconds();
  return report;
}

}  // namespace mgelastic::grid
