#include <dlfcn.h>
#include <gtest/gtest.h>

#include "grid_test_support.hpp"
#include "mgelastic/core/blas_threads.hpp"
#include "mgelastic/core/threads.hpp"
#include "mgelastic/grid/box_problem.hpp"
#include "mgelastic/grid/coarsening.hpp"
#include "mgelastic/grid/level.hpp"
#include "mgelastic/grid/multigrid.hpp"

namespace mgelastic::grid {
namespace {

template <typename Scalar = double>
std::vector<double> solve_with_threads(int threads, double poisson_ratio = 0.45) {
  set_thread_count(threads);
  BoxSpec spec;
  spec.cells = 24;
  spec.poisson_ratio = poisson_ratio;
  Multigrid<3, Scalar> mg(make_box_problem<3>(spec));
  const SolveReport report = mg.run_cycles(4);
  std::vector<double> values = report.residuals;
  for (int f = 0; f <= 3; ++f)
    for (std::size_t k = 0; k < mg.finest().size(); ++k) values.push_back(mg.solution(f, k));
  return values;
}

// Colored blocks fix the traversal order, so the smoothers, residuals and transfers give the
// same numbers, bit for bit, whatever the thread count (and hence the same convergence rate).
TEST(Threads, ResultsDoNotDependOnThreadCount) {
  const auto serial = solve_with_threads(1);
  const auto parallel = solve_with_threads(2);
  set_thread_count(0);
  ASSERT_EQ(serial.size(), parallel.size());
  for (std::size_t i = 0; i < serial.size(); ++i)
    ASSERT_EQ(serial[i], parallel[i]) << "entry " << i;
}

// The fast default: float cycles (compact band rows, colored band and distributive sweeps,
// reused double residual) at nu = 0.48, compared bit for bit between 1 and 2 threads.
TEST(Threads, FloatCyclesDoNotDependOnThreadCount) {
  const auto serial = solve_with_threads<float>(1, 0.48);
  const auto parallel = solve_with_threads<float>(2, 0.48);
  set_thread_count(0);
  ASSERT_EQ(serial.size(), parallel.size());
  for (std::size_t i = 0; i < serial.size(); ++i)
    ASSERT_EQ(serial[i], parallel[i]) << "entry " << i;
}

// The accelerated solve (FGMRES over the interior variables) sums its dot products in fixed
// blocks: its residual history and solution are the same, bit for bit, for 1, 2 and 3 threads,
// on an embedded body in the default mixed precision.
TEST(Threads, AcceleratedSolveDoesNotDependOnThreadCount) {
  auto solve = [](int threads) {
    set_thread_count(threads);
    Multigrid<3, float> mg(test::clamped_ball(20));
    const SolveReport report = mg.solve_accelerated(1e-9, 30, 4);  // restarts included
    EXPECT_TRUE(report.converged) << threads << " threads";
    std::vector<double> values = report.residuals;
    for (int f = 0; f <= 3; ++f)
      for (std::size_t k = 0; k < mg.finest().size(); ++k) values.push_back(mg.solution(f, k));
    return values;
  };
  const auto one = solve(1), two = solve(2), three = solve(3);
  set_thread_count(0);
  ASSERT_EQ(one.size(), two.size());
  ASSERT_EQ(one.size(), three.size());
  for (std::size_t i = 0; i < one.size(); ++i) {
    ASSERT_EQ(one[i], two[i]) << "entry " << i;
    ASSERT_EQ(one[i], three[i]) << "entry " << i;
  }
}

// A multithreaded BLAS (OpenBLAS built with OpenMP follows the OpenMP thread count) would split
// the coarse factorization's dense kernels by thread count, and the test above would fail. The
// solver puts it on one thread. Skipped where the BLAS has no thread count (reference BLAS).
TEST(Threads, CoarseFactorizationRunsOnOneBlasThread) {
  using GetThreads = int (*)();
  const auto get = reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  if (!get) GTEST_SKIP() << "the loaded BLAS is not OpenBLAS";
  set_thread_count(2);
  BoxSpec spec;
  spec.cells = 16;
  const Multigrid<3, double> mg(make_box_problem<3>(spec));
  const int blas_threads = get();
  set_thread_count(0);
  EXPECT_TRUE(use_single_threaded_blas());
  EXPECT_EQ(blas_threads, 1);
}

// The threads build a level's relaxation classes and band rows in lattice ranges, joined in
// order: the same codes, rows, pressure couplings and Fig. 8 sets for any thread count (three
// threads split the lattice unevenly).
TEST(Threads, LevelBuildDoesNotDependOnThreadCount) {
  const ElasticityProblem<3> problem = test::clamped_ball(20);
  const std::vector<CellType> coarse = coarsen_cells(problem.lattice, problem.cells);
  auto build = [&](int threads) {
    set_thread_count(threads);
    return build_level<3, float>(problem.lattice, problem.cells, problem.material,
                                 BoundaryStress<3>{}, &coarse);
  };
  const Level<3, float> one = build(1), two = build(2), three = build(3);
  set_thread_count(0);
  ASSERT_GT(one.band_u.rows(), 0u);
  ASSERT_GT(one.band_p.rows(), 0u);
  ASSERT_GT(one.pre_restriction_rows.size(), 0u);
  for (const Level<3, float>* other : {&two, &three}) {
    EXPECT_TRUE(one.codes.same_values(other->codes));
    for (auto rows : {&Level<3, float>::band_u, &Level<3, float>::band_p}) {
      EXPECT_EQ((one.*rows).target, (other->*rows).target);
      EXPECT_EQ((one.*rows).start, (other->*rows).start);
      EXPECT_EQ((one.*rows).value, (other->*rows).value);
      EXPECT_EQ((one.*rows).constant, (other->*rows).constant);
      EXPECT_EQ((one.*rows).column_index, (other->*rows).column_index);
      EXPECT_EQ((one.*rows).column_field, (other->*rows).column_field);
    }
    EXPECT_EQ(one.band_u_schur_diagonal, other->band_u_schur_diagonal);
    EXPECT_EQ(one.band_u_pressure, other->band_u_pressure);
    EXPECT_EQ(one.band_u_pressure_factor, other->band_u_pressure_factor);
    EXPECT_EQ(one.band_p_inverse, other->band_p_inverse);
    EXPECT_EQ(one.pre_restriction_rows, other->pre_restriction_rows);
    EXPECT_EQ(one.post_prolongation_rows, other->post_prolongation_rows);
  }
}

}  // namespace
}  // namespace mgelastic::grid
