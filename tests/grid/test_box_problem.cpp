#include "mgelastic/grid/box_problem.hpp"

#include <gtest/gtest.h>

#include <string>

#include "mgelastic/core/error.hpp"

namespace mgelastic::grid {
namespace {

// The mixed box's Dirichlet slab: n / 8 cells by default, clamp_cells when given; every other
// real cell interior.
TEST(BoxProblem, ClampCellsSetTheDirichletSlab) {
  BoxSpec spec;
  spec.cells = 16;
  for (const int clamp : {0, 1, 5, 15}) {
    spec.clamp_cells = clamp;
    const auto problem = make_box_problem<3>(spec);
    const int slab = clamp > 0 ? clamp : 2;
    int dirichlet = 0, interior = 0;
    for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(problem.lattice.size()); ++k) {
      const IVec<3> s = problem.lattice.coords(k);
      if (!problem.lattice.is_real(s)) continue;
      const CellType expected = s[0] <= slab ? CellType::DIRICHLET : CellType::INTERIOR;
      EXPECT_EQ(problem.cells[k], expected) << "clamp " << clamp << " at x " << s[0];
      (problem.cells[k] == CellType::DIRICHLET ? dirichlet : interior) += 1;
    }
    EXPECT_EQ(dirichlet, slab * 16 * 16);
    EXPECT_EQ(interior, (16 - slab) * 16 * 16);
  }
}

TEST(BoxProblem, AClampThatLeavesNoBodyIsRefusedNamingTheOption) {
  BoxSpec spec;
  spec.cells = 16;
  for (const int clamp : {16, 40, -1}) {
    spec.clamp_cells = clamp;
    try {
      make_box_problem<3>(spec);
      FAIL() << "clamp " << clamp << " accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("--clamp-cells"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(std::to_string(clamp)), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace mgelastic::grid
