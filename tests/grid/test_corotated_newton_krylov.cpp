// The minimal-residual combination of the co-rotated Newton-Krylov step
// (corotated_newton_krylov.hpp) on small dense systems with a known solution.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "mgelastic/grid/corotated_newton_krylov.hpp"

namespace mgelastic::grid {
namespace {

Eigen::VectorXd vector(double a, double b, double c) {
  Eigen::VectorXd v(3);
  v << a, b, c;
  return v;
}

Eigen::MatrixXd jacobian() {
  Eigen::MatrixXd j(3, 3);
  j << 4, 1, 0, 1, 3, -1, 0, -1, 2;
  return j;
}

// Directions spanning the space: the combination solves J d = r0 exactly.
TEST(MinimalResidualCombination, SpanningDirectionsSolveTheLinearSystem) {
  const Eigen::MatrixXd j = jacobian();
  const Eigen::VectorXd r0 = vector(1, -2, 0.5);
  MinimalResidualCombination combination(r0);
  for (const Eigen::VectorXd& z : {vector(1, 0, 0), vector(1, 1, 0), vector(0, 1, 1)})
    combination.add(z, j * z);
  const Eigen::VectorXd expected = j.fullPivLu().solve(r0);
  EXPECT_LT((combination.correction() - expected).norm(), 1e-12);
  EXPECT_LT(combination.residual().norm(), 1e-12);
}

// One direction: the step length minimizing |r0 - a J z|, a = (J z . r0) / |J z|^2; a repeated
// direction changes nothing (rank-revealing solve, no cancelling coefficients).
TEST(MinimalResidualCombination, OneDirectionTakesTheBestStepLength) {
  const Eigen::MatrixXd j = jacobian();
  const Eigen::VectorXd r0 = vector(1, -2, 0.5), z = vector(0.3, -0.4, 0.2);
  const Eigen::VectorXd w = j * z;
  MinimalResidualCombination combination(r0);
  combination.add(z, w);
  const double a = w.dot(r0) / w.squaredNorm();
  EXPECT_LT((combination.correction() - a * z).norm(), 1e-12);
  EXPECT_NEAR(combination.residual().norm(), (r0 - a * w).norm(), 1e-12);
  EXPECT_LT(combination.residual().norm(), r0.norm());
  combination.add(2 * z, 2 * w);
  EXPECT_NEAR(combination.residual().norm(), (r0 - a * w).norm(), 1e-12);
  EXPECT_TRUE(combination.correction().allFinite());
}

}  // namespace
}  // namespace mgelastic::grid
