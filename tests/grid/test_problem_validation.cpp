#include <gtest/gtest.h>

#include "mgelastic/core/error.hpp"
#include "mgelastic/grid/box_problem.hpp"
#include "mgelastic/grid/multigrid.hpp"

namespace mgelastic::grid {
namespace {

// Expects construction to throw mgelastic::Error whose message contains every fragment.
template <typename F>
void expect_error(F&& make, std::initializer_list<std::string> fragments) {
  try {
    make();
    FAIL() << "expected mgelastic::Error";
  } catch (const Error& e) {
    for (const auto& fragment : fragments)
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos)
          << "message '" << e.what() << "' lacks '" << fragment << "'";
  }
}

ElasticityProblem<3> box(double poisson = 0.3, double youngs = 1e5, int n = 8) {
  BoxSpec spec;
  spec.cells = n;
  spec.poisson_ratio = poisson;
  spec.youngs_modulus = youngs;
  return make_box_problem<3>(spec);
}

TEST(ProblemValidation, PoissonRatioOutsideRangeIsNamed) {
  expect_error([] { Multigrid<3, double> mg(box(0.5)); }, {"poisson_ratio", "[0, 0.5)", "0.5"});
  expect_error([] { Multigrid<3, double> mg(box(-0.1)); }, {"poisson_ratio", "-0.1"});
}

TEST(ProblemValidation, NonPositiveYoungsModulusIsNamed) {
  expect_error([] { Multigrid<3, double> mg(box(0.3, 0.0)); }, {"youngs_modulus", "positive"});
  expect_error([] { Multigrid<3, double> mg(box(0.3, -5.0)); }, {"youngs_modulus", "-5"});
}

TEST(ProblemValidation, TooFewCellsForOneCoarsening) {
  expect_error([] { box(0.3, 1e5, 3); }, {"--n", "at least 4", "3"});
  auto problem = box();
  problem.lattice = Lattice<3>(IVec<3>(8, 8, 3), 0.1);
  problem.cells.assign(problem.lattice.size(), CellType::EXTERIOR);
  expect_error([&] { Multigrid<3, double> mg(problem); }, {"at least 4 cells", "axis 2"});
}

TEST(ProblemValidation, DomainWithoutInteriorCells) {
  auto problem = box();
  for (auto& c : problem.cells)
    if (c == CellType::INTERIOR) c = CellType::EXTERIOR;
  expect_error([&] { Multigrid<3, double> mg(problem); }, {"no interior cell"});
}

TEST(ProblemValidation, TractionOnlyBodyIsSingular) {
  auto problem = box();
  for (auto& c : problem.cells)
    if (c == CellType::DIRICHLET) c = CellType::INTERIOR;
  expect_error([&] { Multigrid<3, double> mg(problem); }, {"touch no Dirichlet", "singular"});
}

TEST(ProblemValidation, NonFiniteLoadsStopTheSolveWithAClearMessage) {
  auto problem = box();
  problem.body_force = [](const Vec<3>&) {
    return Vec<3>::Constant(std::numeric_limits<double>::quiet_NaN());
  };
  Multigrid<3, double> mg(problem);
  expect_error([&] { mg.solve(1e-6, 5); }, {"loads", "not finite"});
}

}  // namespace
}  // namespace mgelastic::grid
