#include <gtest/gtest.h>

#include "mgelastic/grid/box_problem.hpp"
#include "mgelastic/grid/cg_baseline.hpp"
#include "mgelastic/grid/multigrid.hpp"
#include "mgelastic/grid/nonaugmented_system.hpp"
#include "support/tolerances.hpp"

namespace mgelastic::grid {
namespace {

// The augmented (mixed) multigrid solution equals the CG solution of the non-augmented
// system (Eq. 3 with the same boundary treatment) to 1e-8 relative, in double.
TEST(CgBaseline, AugmentedSolutionEqualsNonAugmentedSolution) {
  BoxSpec spec;
  spec.cells = 16;
  spec.poisson_ratio = 0.45;
  const auto problem = make_box_problem<3>(spec);
  Multigrid<3, double> mg(problem);
  // 1e-12: the relative residual's round-off floor in double is ~1e-13 here (it stagnates at
  // 1.0-1.2e-13 after 20 cycles), so 1e-13 passed or failed with the summation order.
  ASSERT_TRUE(mg.solve(1e-12, 60).converged);
  const auto system = assemble_nonaugmented(mg.finest(), problem.boundary_stress);
  const Eigen::SparseMatrix<double, Eigen::RowMajor> a = system.matrix;
  const Eigen::VectorXd rhs = system.right_hand_side(mg.finest());
  Eigen::VectorXd u = Eigen::VectorXd::Zero(rhs.size());
  const CgReport report = conjugate_gradient(a, rhs, u, 1e-14, 20000);
  ASSERT_TRUE(report.converged);
  Eigen::VectorXd mg_u(rhs.size());
  for (std::size_t i = 0; i < system.u_variables.size(); ++i)
    mg_u[i] = mg.finest().at(system.u_variables[i]);
  EXPECT_LE((mg_u - u).norm(), mgelastic::test::kSolveAgreement * u.norm());
}

TEST(CgBaseline, ResidualHistoryDecreasesToTolerance) {
  Eigen::SparseMatrix<double, Eigen::RowMajor> a(3, 3);
  a.insert(0, 0) = 4;
  a.insert(0, 1) = 1;
  a.insert(1, 0) = 1;
  a.insert(1, 1) = 3;
  a.insert(2, 2) = 2;
  Eigen::VectorXd b(3), x = Eigen::VectorXd::Zero(3);
  b << 1, 2, 3;
  const CgReport report = conjugate_gradient(a, b, x, 1e-12, 10);
  EXPECT_TRUE(report.converged);
  EXPECT_LE(report.iterations, 3);  // CG is exact in n steps on an n x n SPD matrix
  EXPECT_LE((a * x - b).norm(), 1e-10);
}

}  // namespace
}  // namespace mgelastic::grid
