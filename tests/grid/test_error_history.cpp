// The error history against the converged solution (grid/error_history.hpp): it falls every
// cycle on the mixed box and reaches the reference within float round-off.
#include <gtest/gtest.h>

#include "mgelastic/grid/box_problem.hpp"
#include "mgelastic/grid/error_history.hpp"

namespace mgelastic::grid {
namespace {

TEST(ErrorHistory, FallsEveryCycleToTheConvergedSolution) {
  BoxSpec spec;
  spec.cells = 16;
  spec.poisson_ratio = 0.45;
  const ErrorHistory history = error_history<3, float>(make_box_problem<3>(spec), {}, 12);
  ASSERT_EQ(history.relative_error.size(), 13U);
  EXPECT_DOUBLE_EQ(history.relative_error.front(), 1.0);  // zero start: the whole solution
  EXPECT_LT(history.reference_residual, 1e-10);
  for (std::size_t c = 1; c < history.relative_error.size(); ++c)
    EXPECT_LT(history.relative_error[c], 0.7 * history.relative_error[c - 1]) << "cycle " << c;
  EXPECT_LT(history.relative_error.back(), 1e-5);
}

}  // namespace
}  // namespace mgelastic::grid
