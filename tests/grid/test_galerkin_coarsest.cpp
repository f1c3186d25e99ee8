#include "mgelastic/grid/galerkin_coarsest.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "mgelastic/core/error.hpp"
#include "mgelastic/grid/box_problem.hpp"
#include "mgelastic/grid/multigrid.hpp"

namespace mgelastic::grid {
namespace {

struct TwoLevelRun {
  double first_ratio = 0;  // residual after the first cycle over the initial one
  double rate = 0;         // geometric mean of the last four cycle ratios
};

// The mixed box at 16 cells, nu 0.495, a clamp `clamp` cells thick, two levels, 12 V(1,1).
TwoLevelRun two_level_run(int clamp, CoarsestOperator op, CoarseDirichletRule rule) {
  BoxSpec spec;
  spec.cells = 16;
  spec.poisson_ratio = 0.495;
  spec.clamp_cells = clamp;
  MultigridOptions options;
  options.max_levels = 2;
  options.coarsest_operator = op;
  options.coarse_dirichlet = rule;
  Multigrid<3, double> mg(make_box_problem<3>(spec), options);
  EXPECT_EQ(mg.levels(), 2);
  const auto& r = mg.run_cycles(12).residuals;
  TwoLevelRun run;
  run.first_ratio = r[1] / r[0];
  run.rate = std::pow(r.back() / r[r.size() - 5], 0.25);
  return run;
}

// A clamp top between coarse faces (3 cells; the coarse cell holding the third and fourth
// layers is Dirichlet under the paper's rule) stalls the two-level cycle at nu 0.495: the free
// fine layer inside the coarse clamp gets no coarse correction, and point Gauss-Seidel reduces
// its near-incompressible modes slowly. With that coarse cell left free and a Galerkin coarse
// operator (which knows the layer is clamped one fine cell down) the rate is the aligned
// clamp's, and the first cycle no longer raises the residual.
TEST(GalerkinCoarsest, MisalignedClampGetsTheAlignedRate) {
  const TwoLevelRun aligned =
      two_level_run(4, CoarsestOperator::REDISCRETIZED, CoarseDirichletRule::ANY_CHILD);
  const TwoLevelRun misaligned =
      two_level_run(3, CoarsestOperator::REDISCRETIZED, CoarseDirichletRule::ANY_CHILD);
  const TwoLevelRun galerkin =
      two_level_run(3, CoarsestOperator::GALERKIN_BAND, CoarseDirichletRule::EVERY_CHILD);
  EXPECT_LT(aligned.rate, 0.3);
  EXPECT_GT(misaligned.rate, 0.6);
  EXPECT_GT(misaligned.first_ratio, 1.0);
  EXPECT_LT(galerkin.rate, 0.3);
  EXPECT_LT(galerkin.first_ratio, 1.0);
}

// Each ingredient alone does not: the Galerkin operator under the paper's rule has no coarse
// variable for the free layer, and the free coarse cell with rediscretized rows is too soft.
TEST(GalerkinCoarsest, NeedsBothTheFreeCoarseCellAndTheGalerkinRows) {
  const TwoLevelRun galerkin_any =
      two_level_run(3, CoarsestOperator::GALERKIN_BAND, CoarseDirichletRule::ANY_CHILD);
  const TwoLevelRun rediscretized_every =
      two_level_run(3, CoarsestOperator::REDISCRETIZED, CoarseDirichletRule::EVERY_CHILD);
  EXPECT_GT(galerkin_any.rate, 0.5);
  EXPECT_GT(rediscretized_every.rate, 0.4);
}

TEST(GalerkinCoarsest, UnknownOperatorNameIsRefusedNamingTheOption) {
  EXPECT_EQ(coarsest_operator("galerkin", "x"), CoarsestOperator::GALERKIN);
  try {
    coarsest_operator("galerkn", "--coarsest-operator");
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("--coarsest-operator"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("galerkn"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace mgelastic::grid
