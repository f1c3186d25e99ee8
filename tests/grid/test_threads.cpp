#include <gtest/gtest.h>

#include "mgelastic/core/threads.hpp"
#include "mgelastic/grid/box_problem.hpp"
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

}  // namespace
}  // namespace mgelastic::grid
