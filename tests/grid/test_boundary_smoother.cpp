#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <random>

#include "grid_test_support.hpp"
#include "mgelastic/grid/band_runs.hpp"
#include "mgelastic/grid/boundary_smoother.hpp"
#include "mgelastic/grid/box_problem.hpp"
#include "mgelastic/grid/coarsening.hpp"
#include "mgelastic/grid/multigrid.hpp"
#include "mgelastic/grid/nonaugmented_system.hpp"
#include "mgelastic/grid/problem_validation.hpp"
#include "mgelastic/grid/residual.hpp"
#include "support/tolerances.hpp"

namespace mgelastic::grid {
namespace {

// Sec. 5.3: the Schur complement S = L_phi - G D^-1 G^T of the eliminated system is symmetric
// negative definite, i.e. A = -S is SPD, on irregular typings with traction corners and
// one-cell-thin features. Checked with random vectors (and the smallest eigenvalue in 2D).
template <int Dim>
void expect_spd(const ElasticityProblem<Dim>& problem, unsigned seed) {
  const auto level =
      build_level<Dim, double>(problem.lattice, problem.cells, problem.material, {}, nullptr);
  const auto system = assemble_nonaugmented(level, BoundaryStress<Dim>{});
  const Eigen::SparseMatrix<double>& a = system.matrix;
  ASSERT_GT(a.rows(), 50);
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  for (int trial = 0; trial < 10; ++trial) {
    Eigen::VectorXd x(a.rows()), y(a.rows());
    for (Eigen::Index i = 0; i < x.size(); ++i) {
      x[i] = normal(rng);
      y[i] = normal(rng);
    }
    const double xay = x.dot(a * y), yax = y.dot(a * x);
    EXPECT_NEAR(xay, yax, mgelastic::test::kSymmetry * x.norm() * (a * y).norm() * 10);
    EXPECT_GT(x.dot(a * x), 0.0);
  }
}

TEST(SchurComplement, SymmetricNegativeDefiniteOnIrregularCells2D) {
  for (unsigned seed : {1u, 2u, 3u})
    expect_spd(test::irregular_problem<2>(20, seed, {1e5, 0.49}), seed);
}

TEST(SchurComplement, SymmetricNegativeDefiniteOnIrregularCells3D) {
  for (unsigned seed : {4u, 5u}) expect_spd(test::irregular_problem<3>(9, seed, {1e5, 0.3}), seed);
}

// A deterministic irregular body: a notch (concave traction corners) and a one-cell-thin bar.
// (Random typings can contain pieces hinged on a single face, which are genuine mechanisms:
// the shear stresses beside that face are traction-free, so the piece rotates freely.)
TEST(SchurComplement, SmallestEigenvalueIsPositive) {
  const auto problem =
      test::unit_box<2>(12, {1e5, 0.45}, [](const IVec<2>& s) { return s[0] == 1; });
  auto cells = problem.cells;
  for (std::size_t k = 0; k < cells.size(); ++k) {
    const IVec<2> s = problem.lattice.coords(k);
    if (cells[k] != CellType::INTERIOR) continue;
    const bool notch = s[0] >= 5 && s[0] <= 7 && s[1] >= 4 && s[1] <= 6;
    const bool beyond_block = s[0] >= 8 && s[1] != 8;  // keeps the thin bar y = 8
    if (notch || beyond_block) cells[k] = CellType::EXTERIOR;
  }
  auto shaped = problem;
  shaped.cells = cells;
  validate(shaped);
  const auto level =
      build_level<2, double>(shaped.lattice, shaped.cells, shaped.material, {}, nullptr);
  const auto system = assemble_nonaugmented(level, BoundaryStress<2>{});
  const Eigen::MatrixXd dense = Eigen::MatrixXd(system.matrix);
  EXPECT_LT((dense - dense.transpose()).norm(), mgelastic::test::kSymmetry * dense.norm());
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(dense);
  // Definite, not merely semi-definite: well above round-off of the largest eigenvalue.
  EXPECT_GT(eigen.eigenvalues().minCoeff(), 1e-8 * eigen.eigenvalues().maxCoeff());
}

// Gauss-Seidel on the band's Schur system converges: with the interior held fixed, repeated
// band sweeps drive every band momentum residual (and the eliminated pressures' rows) to zero.
TEST(BandSmoother, BandSweepsConvergeWithInteriorFixed) {
  BoxSpec spec;
  spec.cells = 12;
  spec.poisson_ratio = 0.49;
  auto problem = make_box_problem<3>(spec);
  auto level =
      build_level<3, double>(problem.lattice, problem.cells, problem.material, {}, nullptr);
  std::mt19937 rng(2);
  std::normal_distribution<double> normal;
  for (int f = 0; f <= 3; ++f)
    for (std::size_t k = 0; k < level.size(); ++k)
      if (level.kind(f, k) == VarKind::INTERIOR) level.b[f][k] = normal(rng);
  auto band_norm = [&] {
    compute_residual(level);
    double sum = 0;
    for (int f = 0; f <= 3; ++f)
      for (std::size_t k = 0; k < level.size(); ++k)
        if (level.relaxation(f, k) == Relaxation::BAND) sum += level.r[f][k] * level.r[f][k];
    return std::sqrt(sum);
  };
  const double before = band_norm();
  const auto start = level;
  band_gauss_seidel(level, 400, BandSweepOrder::BAND_WIDE);
  EXPECT_LT(band_norm(), 1e-6 * before);
  // Block-local: one call relaxes each block to its own solution with its neighbours fixed (a
  // multiplicative Schwarz sweep over the colours); repeated calls converge the whole band.
  level = start;
  for (int call = 0; call < 400 / 3; ++call)
    band_gauss_seidel(level, 3, BandSweepOrder::BLOCK_LOCAL);
  EXPECT_LT(band_norm(), 1e-6 * before);
}

// After back-substitution the finite-difference normal stress at every traction face equals
// the prescribed value: the boundary conditions hold exactly (Sec. 5.3).
TEST(BandSmoother, BackSubstitutionSatisfiesNormalTractions) {
  BoxSpec spec;
  spec.cells = 8;
  spec.poisson_ratio = 0.3;
  auto problem = make_box_problem<2>(spec);
  const double sigma = 123.0;
  auto level = build_level<2, double>(
      problem.lattice, problem.cells, problem.material,
      [&](int, int, const Vec<2>&) { return sigma; }, nullptr);
  std::mt19937 rng(4);
  std::normal_distribution<double> normal;
  for (int f = 0; f <= 2; ++f)
    for (std::size_t k = 0; k < level.size(); ++k)
      if (level.kind(f, k) == VarKind::INTERIOR) level.x[f][k] = 1e-3 * normal(rng);
  back_substitute_traction(level);
  ASSERT_FALSE(level.traction.normal.empty());
  const double mu = level.mu, h = level.lattice.h;
  for (const auto& rule : level.traction.normal) {
    const double upper = rule.sign > 0 ? level.at(rule.face) : level.at(rule.partner);
    const double lower = rule.sign > 0 ? level.at(rule.partner) : level.at(rule.face);
    const double p_ii = 2 * mu * (upper - lower) / h - mu * level.at(rule.cell);
    EXPECT_NEAR(p_ii, sigma, 1e-9 * sigma);
  }
}

// The compact band rows the sweeps read (band_kernel.hpp) are the CSR rows of band_u: the same
// values at the same columns in the same order, so every row sums bit for bit alike, on an
// irregular typing (many distinct patterns) and on the box (few patterns shared by many rows).
template <int Dim>
void expect_kernel_matches_rows(const ElasticityProblem<Dim>& problem) {
  auto level =
      build_level<Dim, float>(problem.lattice, problem.cells, problem.material, {}, nullptr);
  const auto& rows = level.band_u;
  const auto& kernel = level.band_kernel;
  ASSERT_GT(rows.rows(), 10u);
  ASSERT_EQ(kernel.rows(), rows.rows());
  EXPECT_LT(kernel.patterns(), kernel.rows());
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> uniform(-1, 1);
  for (auto& field : level.x)
    for (float& v : field) v = uniform(rng);
  for (std::size_t m = 0; m < rows.rows(); ++m) {
    float csr = 0, compact = 0;
    for (std::uint32_t e = rows.start[m]; e < rows.start[m + 1]; ++e)
      csr += rows.value[e] * level.x[rows.column_field[e]][rows.column_index[e]];
    const std::uint32_t p = kernel.pattern[m];
    for (std::uint32_t e = kernel.start[p]; e < kernel.start[p + 1]; ++e)
      compact += kernel.entry_value[e] *
                 level.x[kernel.entry_field[e]][kernel.target[m] + kernel.entry_offset[e]];
    ASSERT_EQ(csr, compact) << "band row " << m;
    ASSERT_EQ(kernel.schur_diagonal[p], level.band_u_schur_diagonal[m]) << "band row " << m;
    ASSERT_EQ(kernel.field[m], rows.target_field[m]);
  }
}

TEST(BandKernel, CompactRowsEqualTheCsrRows) {
  expect_kernel_matches_rows(test::irregular_problem<3>(12, 4u, {1e5, 0.45}));
  expect_kernel_matches_rows(test::irregular_problem<2>(24, 2u, {1e5, 0.49}));
  BoxSpec spec;
  spec.cells = 16;
  spec.poisson_ratio = 0.48;
  expect_kernel_matches_rows(make_box_problem<3>(spec));
}

// The Fig. 8 rows' extra sweeps run block by block over colored schedules: every row of the
// subset appears exactly once, in the block that holds its target (so the blocks of one color,
// a block apart, touch disjoint variables), in band_u order within the block.
template <int Dim>
void expect_schedule_holds(const Level<Dim, float>& level,
                           const typename Level<Dim, float>::RowSchedule& schedule,
                           const std::vector<std::uint32_t>& rows) {
  std::vector<std::uint32_t> scheduled;
  for (int c = 0; c < BlockPartition<Dim>::color_count; ++c) {
    ASSERT_EQ(schedule[c].size(), level.blocks.colors[c].size());
    for (std::size_t b = 0; b < schedule[c].size(); ++b) {
      const Block<Dim>& block = level.blocks.colors[c][b];
      EXPECT_TRUE(std::is_sorted(schedule[c][b].begin(), schedule[c][b].end()));
      for (std::uint32_t m : schedule[c][b]) {
        const IVec<Dim> s = level.lattice.coords(level.band_kernel.target[m]);
        for (int a = 0; a < Dim; ++a) {
          EXPECT_GE(s[a], block.lo[a]) << "row " << m;
          EXPECT_LT(s[a], block.hi[a]) << "row " << m;
        }
        scheduled.push_back(m);
      }
    }
  }
  std::sort(scheduled.begin(), scheduled.end());
  EXPECT_EQ(scheduled, rows);
}

TEST(BandSmoother, RelocationSchedulesHoldTheFig8RowsBlockByBlock) {
  BoxSpec spec;
  spec.cells = 40;  // blocks of 128 x 8 x 8 cells, cut by the box
  spec.poisson_ratio = 0.48;
  const ElasticityProblem<3> problem = make_box_problem<3>(spec);
  const std::vector<CellType> coarse_cells = coarsen_cells(problem.lattice, problem.cells);
  const auto fine =
      build_level<3, float>(problem.lattice, problem.cells, problem.material, {}, &coarse_cells);
  ASSERT_GT(fine.pre_restriction_rows.size(), 100u);
  ASSERT_GT(fine.post_prolongation_rows.size(), 100u);
  expect_schedule_holds(fine, fine.pre_restriction_schedule, fine.pre_restriction_rows);
  expect_schedule_holds(fine, fine.post_prolongation_schedule, fine.post_prolongation_rows);
  // The hierarchy keeps a schedule only where its set is not the whole band (relocation_sweeps
  // sweeps the whole band then).
  const Multigrid<3, float> mg(problem);
  const Level<3, float>& level = mg.finest();
  int dropped = 0;
  for (const auto& [schedule, rows] :
       {std::pair{&level.pre_restriction_schedule, &level.pre_restriction_rows},
        std::pair{&level.post_prolongation_schedule, &level.post_prolongation_rows}}) {
    if (rows->size() < level.band_kernel.rows()) {
      expect_schedule_holds(level, *schedule, *rows);
      continue;
    }
    for (const auto& color : *schedule) EXPECT_TRUE(color.empty());
    ++dropped;
  }
  EXPECT_EQ(dropped, 1);  // here every band row reads a coarse boundary correction
}

// Run-wise band relaxation (band_runs.hpp) keeps the step-by-step sweep's order: after three
// band sweeps from random values every unknown equals the step-by-step result up to round-off, on
// the mixed and the all-Dirichlet box (long runs along x, and along y on the faces across x) and on
// an irregular typing (few, short runs), and the runs hold most of the box's band work. (The random
// irregular typings hold a few band rows without entries, faces of a cell pair one cell thin in two
// directions at the lattice's last layer: their zero pivot gives inf/NaN in both sweeps, which must
// then agree there too; the comparison covers the finite values. The meshes' bands have none: 0 of
// 18114 rows on the armadillo at 64, 0 of 14974 on the bunny at 48.)
template <int Dim>
void expect_runs_equal_steps(const ElasticityProblem<Dim>& problem, double min_run_share,
                             BandSweepOrder order) {
  const Multigrid<Dim, double> mg(problem);
  auto level = mg.finest();
  ASSERT_TRUE(level.band_runs.valid_for(level.band_kernel.rows()));
  const auto& runs = level.band_runs;
  EXPECT_GE(static_cast<double>(runs.row_relaxations_in_runs),
            min_run_share * static_cast<double>(runs.row_relaxations));
  std::printf("band row relaxations in runs: %zu of %zu\n", runs.row_relaxations_in_runs,
              runs.row_relaxations);
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  for (int f = 0; f <= Dim; ++f) {
    for (std::size_t k = 0; k < level.size(); ++k) {
      if (level.kind(f, k) != VarKind::INTERIOR) continue;
      level.x[f][k] = normal(rng);
      level.b[f][k] = 1e5 * normal(rng);
    }
  }
  const auto start = level;
  auto reference = level;
  reference.band_runs = {};  // invalid: the step-by-step sweeps
  band_gauss_seidel(level, 3, order);
  band_gauss_seidel(reference, 3, order);
  double scale = 0, difference = 0, moved = 0;
  std::size_t finite = 0, nan_mismatch = 0;
  for (int f = 0; f <= Dim; ++f) {
    for (std::size_t k = 0; k < level.size(); ++k) {
      const double a = level.x[f][k], b = reference.x[f][k];
      nan_mismatch += std::isfinite(a) != std::isfinite(b);
      if (!std::isfinite(b)) continue;
      ++finite;
      scale = std::max(scale, std::abs(b));
      difference = std::max(difference, std::abs(a - b));
      moved = std::max(moved, std::abs(b - start.x[f][k]));
    }
  }
  EXPECT_EQ(nan_mismatch, 0u);
  EXPECT_GT(finite, (Dim + 1) * level.size() / 2);
  EXPECT_GT(moved, 0.1 * scale) << "the sweeps must move the unknowns";
  EXPECT_LE(difference, 1e-11 * scale);
}

TEST(BandRuns, RunWiseSweepEqualsStepByStepSweep) {
  for (const BandSweepOrder order : {BandSweepOrder::BLOCK_LOCAL, BandSweepOrder::BAND_WIDE}) {
    for (const BoxBoundary boundary : {BoxBoundary::MIXED, BoxBoundary::DIRICHLET}) {
      BoxSpec spec;
      spec.cells = 16;
      spec.poisson_ratio = 0.48;
      spec.boundary = boundary;
      expect_runs_equal_steps(make_box_problem<3>(spec), 0.8, order);  // along x and y: 89 %
      spec.cells = 40;
      expect_runs_equal_steps(make_box_problem<2>(spec), 0.85, order);  // 95 %
    }
    expect_runs_equal_steps(test::irregular_problem<3>(12, 4u, {1e5, 0.45}), 0.0, order);
    expect_runs_equal_steps(test::irregular_problem<2>(24, 2u, {1e5, 0.49}), 0.0, order);
  }
}

// Random interior values and right-hand sides on the finest level of `problem`.
template <int Dim>
Level<Dim, double> randomized_finest(const ElasticityProblem<Dim>& problem) {
  const Multigrid<Dim, double> mg(problem);
  Level<Dim, double> level = mg.finest();
  std::mt19937 rng(11);
  std::normal_distribution<double> normal;
  for (int f = 0; f <= Dim; ++f)
    for (std::size_t k = 0; k < level.size(); ++k) {
      if (level.kind(f, k) != VarKind::INTERIOR) continue;
      level.x[f][k] = normal(rng);
      level.b[f][k] = 1e5 * normal(rng);
    }
  return level;
}

template <int Dim>
double max_abs_difference(const Level<Dim, double>& a, const Level<Dim, double>& b) {
  double worst = 0;
  for (int f = 0; f <= Dim; ++f)
    for (std::size_t k = 0; k < a.size(); ++k)
      worst = std::max(worst, std::abs(a.x[f][k] - b.x[f][k]));
  return worst;
}

// The band's Schur residual: the residual of its momentum rows with the pressures exact.
template <int Dim>
double band_residual_norm(Level<Dim, double> level) {
  update_band_pressures(level);
  compute_residual(level);
  double sum = 0;
  const auto& kernel = level.band_kernel;
  for (std::size_t m = 0; m < kernel.rows(); ++m) {
    const double r = level.r[kernel.field[m]][kernel.target[m]];
    sum += r * r;
  }
  return std::sqrt(sum);
}

// BandSweepOrder (boundary_smoother.hpp): one sweep relaxes the same rows in the same order in
// both orders (bit-identical); three sweeps differ (the block-local order is really another
// order) and reduce the band's Schur residual about as much (within 2x of each other, both by
// more than 10x on the mixed box and an embedded ball, with runs and single rows).
TEST(BandSweepOrder, OneSweepIsTheSameThreeSweepsConvergeAlike) {
  BoxSpec spec;
  spec.cells = 24;  // blocks of 128 x 8 x 8: three along y and z, four colors used
  spec.poisson_ratio = 0.48;
  const std::array<ElasticityProblem<3>, 2> problems = {make_box_problem<3>(spec),
                                                        test::clamped_ball(24)};
  for (const auto& problem : problems) {
    const Level<3, double> start = randomized_finest(problem);
    Level<3, double> local = start, wide = start;
    band_gauss_seidel(local, 1, BandSweepOrder::BLOCK_LOCAL);
    band_gauss_seidel(wide, 1, BandSweepOrder::BAND_WIDE);
    EXPECT_EQ(max_abs_difference(local, wide), 0.0);
    local = start;
    wide = start;
    band_gauss_seidel(local, 3, BandSweepOrder::BLOCK_LOCAL);
    band_gauss_seidel(wide, 3, BandSweepOrder::BAND_WIDE);
    EXPECT_GT(max_abs_difference(local, wide), 0.0) << "the orders must differ";
    const double initial = band_residual_norm(start);
    const double r_local = band_residual_norm(local), r_wide = band_residual_norm(wide);
    std::printf("band Schur residual %.4g -> block-local %.4g, band-wide %.4g\n", initial, r_local,
                r_wide);
    EXPECT_LT(r_local, 0.1 * initial);
    EXPECT_LT(r_wide, 0.1 * initial);
    EXPECT_LT(r_local, 2 * r_wide);
    EXPECT_LT(r_wide, 2 * r_local);
  }
}

// BandRhs (boundary_smoother.hpp): a CURRENT call reads the right-hand sides of the last
// refresh and not b, so it equals a REFRESH call exactly when b has not changed since, and still
// sweeps against the refreshed b after b changed; a REFRESH call sees the new b.
TEST(BandRhs, CurrentCallsReadTheLastRefresh) {
  const ElasticityProblem<3> problem = test::clamped_ball(16);
  Level<3, double> start = randomized_finest(problem);
  refresh_band_rhs(start);
  Level<3, double> current = start, fresh = start;
  band_gauss_seidel(current, 2, BandSweepOrder::BLOCK_LOCAL, BandRhs::CURRENT);
  band_gauss_seidel(fresh, 2, BandSweepOrder::BLOCK_LOCAL, BandRhs::REFRESH);
  EXPECT_EQ(max_abs_difference(current, fresh), 0.0);

  // Change b at every band row's own variable: only the REFRESH call sees it.
  Level<3, double> changed = start;
  const BandKernel<double>& kernel = changed.band_kernel;
  for (std::size_t m = 0; m < kernel.rows(); ++m)
    changed.b[kernel.field[m]][kernel.target[m]] += 1e3;
  Level<3, double> stale = changed, refreshed = changed;
  band_gauss_seidel(stale, 2, BandSweepOrder::BLOCK_LOCAL, BandRhs::CURRENT);
  band_gauss_seidel(refreshed, 2, BandSweepOrder::BLOCK_LOCAL, BandRhs::REFRESH);
  EXPECT_EQ(max_abs_difference(stale, current), 0.0) << "CURRENT must not read b";
  EXPECT_GT(max_abs_difference(refreshed, current), 0.0) << "REFRESH must read b";
}

// The run schedule (band_runs.hpp) keeps only blocks with band work, largest first in each
// color, and loses none: the blocks' work adds up to every row relaxation of a sweep, on the box
// (wall blocks ~8x the others) and on an embedded ball (many blocks without band).
TEST(BandRuns, ScheduleHoldsEveryBlockWithWorkLargestFirst) {
  BoxSpec spec;
  spec.cells = 40;
  spec.poisson_ratio = 0.48;
  for (const auto& problem : {make_box_problem<3>(spec), test::clamped_ball(40)}) {
    const Multigrid<3, float> mg(problem);
    const Level<3, float>& level = mg.finest();
    const BandRuns<3, float>& runs = level.band_runs;
    ASSERT_TRUE(runs.valid_for(level.band_kernel.rows()));
    std::size_t total = 0, blocks = 0;
    for (const auto& color : runs.schedule) {
      std::size_t previous = SIZE_MAX;
      for (const auto& items : color) {
        const std::size_t work = band_block_work(level, runs, items);
        EXPECT_GT(work, 0u);
        EXPECT_LE(work, previous) << "blocks of a color must come largest first";
        previous = work;
        total += work;
        ++blocks;
      }
    }
    EXPECT_EQ(total, runs.row_relaxations);
    EXPECT_GT(blocks, 8u);
  }
}

}  // namespace
}  // namespace mgelastic::grid
