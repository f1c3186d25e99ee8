// The V-cycle's byte model (cycle_roofline.hpp): volume terms scale with the cells, each term
// equals its hand count, and the roofline rows add up to the cycle.
#include <gtest/gtest.h>

#include "mgelastic/grid/box_problem.hpp"
#include "mgelastic/grid/cycle_roofline.hpp"
#include "mgelastic/grid/multigrid.hpp"

namespace mgelastic::grid {
namespace {

// Doubling the cells per axis multiplies the volume terms by ~8 (the band terms grow ~4x, so the
// whole-cycle phases that mix both stay between 4x and 8x plus the lattice's ghost ring).
TEST(CycleRoofline, VolumePhasesScaleWithTheCells) {
  Multigrid<3, float> coarse(make_box_problem<3>({.cells = 16}));
  Multigrid<3, float> fine(make_box_problem<3>({.cells = 32}));
  const PhaseSeconds a = cycle_bytes(coarse), b = cycle_bytes(fine);
  EXPECT_NEAR(distributive_sweep_bytes(fine.finest()) / distributive_sweep_bytes(coarse.finest()),
              8.0, 1e-12);
  for (double ratio : {b.interior_smoothing / a.interior_smoothing, b.residual / a.residual,
                       b.prolongation / a.prolongation}) {
    EXPECT_GT(ratio, 4.0);
    EXPECT_LT(ratio, 9.0);
  }
  // The cycle restricts fresh residuals (residual_restriction.hpp): the residual row holds it.
  EXPECT_EQ(a.restriction, 0.0);
  EXPECT_EQ(b.restriction, 0.0);
  EXPECT_GT(b.boundary_smoothing / a.boundary_smoothing, 3.0);
  EXPECT_LT(b.boundary_smoothing / a.boundary_smoothing, 9.0);
}

// Hand counts on the finest level of an 8^3 box (10^3 padded lattice, 512 real cells), float.
TEST(CycleRoofline, VolumeTermsEqualTheirHandCount) {
  Multigrid<3, float> mg(make_box_problem<3>({.cells = 8}), {.max_levels = 2});
  const auto& fine = mg.level(0);
  const auto& coarse = mg.level(1);
  ASSERT_EQ(fine.size(), 1000u);
  ASSERT_EQ(coarse.size(), 216u);
  // Block-wise sweep: x and b read, x written (3 x 4 fields x 4 bytes), four relaxation bytes
  // and the cell type: 48 + 5 = 53 per real cell.
  EXPECT_DOUBLE_EQ(distributive_sweep_bytes(fine), 512.0 * 53);
  // Fine r read (4 fields) + coarse x, b written and coarse kind read.
  EXPECT_DOUBLE_EQ(restriction_bytes(fine, coarse), 1000.0 * 4 * 4 + 216.0 * 4 * (2 * 4 + 1));
  // The cycle fuses it with the residual: no r written or read, the coarse writes stay.
  EXPECT_TRUE(mg.fuses_restriction(0));
  EXPECT_DOUBLE_EQ(fused_residual_restriction_bytes(fine, coarse),
                   residual_bytes(fine) - 1000.0 * 4 * 4 + 216.0 * 4 * (2 * 4 + 1));
  // Coarse x and kind read, fine kind read and x read + written.
  EXPECT_DOUBLE_EQ(prolongation_bytes(coarse, fine), 216.0 * 4 * (4 + 1) + 1000.0 * 4 * (8 + 1));
  // Stencil pass: x, b, relaxation read and r written per field, plus the band rows (> 0).
  EXPECT_GT(residual_bytes(fine), 1000.0 * 4 * (3 * 4 + 1));
  EXPECT_GT(band_gauss_seidel_bytes(fine, 2), band_gauss_seidel_bytes(fine, 1));
}

TEST(CycleRoofline, RowsAddUpToTheCycle) {
  Multigrid<3, float> mg(make_box_problem<3>({.cells = 16}));
  const SolveReport report = mg.run_cycles(2);
  const CycleRoofline table = cycle_roofline(mg, report, 10.0);
  ASSERT_EQ(static_cast<int>(table.phases.size()), PhaseSeconds::count);
  double seconds = 0, bytes = 0;
  for (const auto& row : table.phases) {
    seconds += row.seconds;
    bytes += row.bytes;
    EXPECT_GE(row.bytes, 0.0) << row.name;
    if (row.seconds > 0) {
      EXPECT_DOUBLE_EQ(row.triad_fraction, row.gb_per_s / 10.0) << row.name;
    }
  }
  EXPECT_DOUBLE_EQ(table.total.bytes, bytes);
  EXPECT_NEAR(table.unattributed_seconds, table.total.seconds - seconds, 1e-12);
  EXPECT_GT(table.phases[6].bytes, 0.0);  // float: the mixed-precision refinement
}

}  // namespace
}  // namespace mgelastic::grid
