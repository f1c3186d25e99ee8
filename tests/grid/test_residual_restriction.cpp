#include "mgelastic/grid/residual_restriction.hpp"

#include <gtest/gtest.h>

#include <random>

#include "grid_test_support.hpp"
#include "mgelastic/core/threads.hpp"
#include "mgelastic/grid/box_problem.hpp"
#include "mgelastic/grid/multigrid.hpp"
#include "mgelastic/grid/residual.hpp"
#include "mgelastic/grid/transfer.hpp"

namespace mgelastic::grid {
namespace {

// Random x and b on the live chunks of a level (the rest holds zeros with its pages released),
// Dirichlet, inactive and padding entries included: the fused pass must zero what has no
// equation exactly as update_residual does.
template <int Dim, typename Scalar>
void randomize(Level<Dim, Scalar>& level, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  for (int f = 0; f <= Dim; ++f)
    for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(level.size()); ++k) {
      if (!level.live.any_live(k, k + 1)) continue;
      level.x[f][k] = static_cast<Scalar>(1e-3 * normal(rng));
      level.b[f][k] = static_cast<Scalar>(normal(rng));
    }
}

// The fused residual + restriction of level 0 into level 1 equals update_residual followed by
// restrict_residual, bit for bit, on 1 and 2 threads; the coarse unknowns are zeroed.
template <int Dim, typename Scalar>
void expect_fused_equals_separate(const ElasticityProblem<Dim>& problem) {
  Multigrid<Dim, Scalar> mg(problem);
  ASSERT_GE(mg.levels(), 2);
  Level<Dim, Scalar>& fine = mg.level(0);
  randomize(fine, 7);
  EXPECT_TRUE(fine.r[0].empty());  // the cycle's levels keep no residual array
  const BandRowPlanes planes = band_row_planes(fine);
  ASSERT_TRUE(planes.valid_for(fine));
  ASSERT_GT(planes.momentum_rows.size() + planes.rows_in_lines, 0u);

  Level<Dim, Scalar> separate = mg.level(1);
  update_residual(fine);
  restrict_residual(fine, separate);
  std::size_t nonzero = 0;
  for (int threads : {1, 2}) {
    set_thread_count(threads);
    Level<Dim, Scalar> fused = mg.level(1);
    randomize(fused, 11);  // stale coarse values: the fused pass overwrites or zeroes them all
    ResidualWindows<Scalar> windows;
    restrict_fresh_residual(fine, planes, fused, windows);
    for (int f = 0; f <= Dim; ++f)
      for (std::size_t k = 0; k < fused.size(); ++k) {
        ASSERT_EQ(fused.b[f][k], separate.b[f][k])
            << threads << " threads, field " << f << " at " << k;
        ASSERT_EQ(fused.x[f][k], Scalar(0)) << "field " << f << " at " << k;
        nonzero += separate.b[f][k] != Scalar(0);
      }
  }
  set_thread_count(0);
  EXPECT_GT(nonzero, 0u);
}

ElasticityProblem<2> mixed_box_2d() {
  BoxSpec spec;
  spec.cells = 40;
  spec.poisson_ratio = 0.48;
  return make_box_problem<2>(spec);
}

ElasticityProblem<3> mixed_box_3d() {
  BoxSpec spec;
  spec.cells = 24;
  spec.poisson_ratio = 0.48;
  return make_box_problem<3>(spec);
}

TEST(ResidualRestriction, FusedEqualsResidualThenRestrictionOnBoxes) {
  expect_fused_equals_separate<2, float>(mixed_box_2d());
  expect_fused_equals_separate<2, double>(mixed_box_2d());
  expect_fused_equals_separate<3, float>(mixed_box_3d());
  expect_fused_equals_separate<3, double>(mixed_box_3d());
}

// An embedded body: band rows of every shape, released pages, planes without any variable.
TEST(ResidualRestriction, FusedEqualsResidualThenRestrictionOnEmbeddedBodies) {
  expect_fused_equals_separate<3, float>(test::clamped_ball(32));
  expect_fused_equals_separate<2, double>(test::irregular_problem<2>(48, 3, {1e5, 0.45}));
}

// Band runs make lines (band_row_planes.hpp): on a box most band rows are in one, and the norm
// through them is the row-by-row norm, bit for bit, on 1 and 2 threads.
TEST(ResidualRestriction, LinesHoldMostBoxBandRowsAndKeepTheNorm) {
  Multigrid<3, float> mg(mixed_box_3d());
  Level<3, float>& fine = mg.level(0);
  randomize(fine, 3);
  const BandRowPlanes planes = band_row_planes(fine);
  ASSERT_TRUE(planes.valid_for(fine));
  EXPECT_GT(planes.rows_in_lines, fine.band_kernel.rows() / 2);
  const double row_by_row = fresh_residual_norm(fine);
  for (int threads : {1, 2}) {
    set_thread_count(threads);
    EXPECT_EQ(fresh_residual_norm(fine, &planes), row_by_row) << threads << " threads";
  }
  set_thread_count(0);
  EXPECT_GT(row_by_row, 0.0);
}

// Whoever asks for a residual array still gets one (the monitor, FGMRES, single precision).
TEST(ResidualRestriction, LevelsGetAResidualArrayOnRequest) {
  Multigrid<3, float> mg(mixed_box_3d());
  Level<3, float>& fine = mg.level(0);
  ASSERT_TRUE(fine.r[0].empty());
  randomize(fine, 5);
  const double norm = compute_residual(fine);
  EXPECT_EQ(fine.r[0].size(), fine.size());
  EXPECT_GT(norm, 0.0);
}

}  // namespace
}  // namespace mgelastic::grid
