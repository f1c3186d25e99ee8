#include "mgelastic/grid/galerkin_band_rows.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include "grid_test_support.hpp"
#include "mgelastic/core/error.hpp"
#include "mgelastic/grid/boundary_smoother.hpp"
#include "mgelastic/grid/box_problem.hpp"
#include "mgelastic/grid/coarsening.hpp"
#include "mgelastic/grid/live_chunks.hpp"
#include "mgelastic/grid/multigrid.hpp"
#include "mgelastic/grid/residual.hpp"
#include "mgelastic/grid/transfer.hpp"

namespace mgelastic::grid {
namespace {

struct TwoLevels {
  Level<3, double> fine, coarse;
};

// The finest level and the next one as Multigrid builds them (coarse clamps at the finest
// depth), with the every-child Dirichlet rule.
TwoLevels two_levels(const ElasticityProblem<3>& problem) {
  const auto coarse_lattice = coarsen(problem.lattice);
  const auto coarse_cells =
      coarsen_cells(problem.lattice, problem.cells, CoarseDirichletRule::EVERY_CHILD);
  TwoLevels levels{
      build_level<3, double>(problem.lattice, problem.cells, problem.material, {}, &coarse_cells),
      build_level<3, double>(coarse_lattice, coarse_cells, problem.material, {}, nullptr, 0.0, 0,
                             {}, 0.5 * problem.lattice.h,
                             finest_dirichlet_wall_layers(problem.lattice, problem.cells,
                                                          coarse_lattice, coarse_cells, 2, true))};
  return levels;
}

// Column J of P (fine x after prolongating e_J with the coarse traction back-substitution) and
// of A_f P (minus the fine residual for b = 0), by running the cycle's own operators.
struct Probe {
  std::map<std::uint32_t, double> p, ap;
};
Probe probe(Level<3, double>& fine, Level<3, double>& coarse, std::uint32_t column) {
  for (auto* level : {&fine, &coarse})
    for (int f = 0; f <= 3; ++f) {
      zero_live(level->x[f], level->live);
      zero_live(level->b[f], level->live);
    }
  coarse.at(column) = 1.0;
  back_substitute_traction(coarse);
  prolongate_correction(coarse, fine);
  back_substitute_traction(fine);
  ensure_residual_storage(fine);
  update_residual(fine);
  Probe out;
  for (int f = 0; f < 3; ++f)
    for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(fine.size()); ++k) {
      if (fine.kind(f, k) != VarKind::INTERIOR) continue;
      if (fine.x[f][k] != 0) out.p[fine.global(f, k)] = fine.x[f][k];
      if (fine.r[f][k] != 0) out.ap[fine.global(f, k)] = -fine.r[f][k];
    }
  return out;
}

// The locally computed Galerkin terms equal P^T A_f P / 8 probed with the cycle's operators,
// entry by entry, on every band row.
void expect_terms_equal_probed_product(const ElasticityProblem<3>& problem) {
  TwoLevels levels = two_levels(problem);
  Level<3, double>& fine = levels.fine;
  Level<3, double>& coarse = levels.coarse;
  const auto terms = galerkin_band_displacement_terms(fine, coarse);
  ASSERT_EQ(terms.size(), coarse.band_u.rows());
  ASSERT_GT(terms.size(), 0u);
  std::map<std::uint32_t, Probe> probes;
  for (int f = 0; f < 3; ++f)
    for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(coarse.size()); ++k)
      if (coarse.kind(f, k) == VarKind::INTERIOR)
        probes[coarse.global(f, k)] = probe(fine, coarse, coarse.global(f, k));
  double largest_error = 0.0, largest = 0.0;
  std::size_t compared = 0;
  for (std::size_t m = 0; m < terms.size(); ++m) {
    const Probe& row = probes.at(coarse.band_u.target[m]);
    std::map<std::uint32_t, double> explicit_row;
    for (const RowTerm& t : terms[m]) explicit_row[t.variable] = t.coefficient;
    for (const auto& [column, column_probe] : probes) {
      double product = 0.0;
      for (const auto& [i, p_i] : row.p) {
        const auto it = column_probe.ap.find(i);
        if (it != column_probe.ap.end()) product += p_i * it->second;
      }
      product /= 8.0;
      const auto it = explicit_row.find(column);
      const double value = it == explicit_row.end() ? 0.0 : it->second;
      largest_error = std::max(largest_error, std::abs(value - product));
      largest = std::max(largest, std::abs(product));
      ++compared;
    }
  }
  EXPECT_GT(largest, 0.0);
  EXPECT_LT(largest_error, 1e-9 * largest) << compared << " entries compared";
}

TEST(GalerkinBandRows, EqualTheProbedProductOnAMisalignedClamp) {
  BoxSpec spec;
  spec.cells = 12;
  spec.poisson_ratio = 0.495;
  spec.clamp_cells = 3;
  expect_terms_equal_probed_product(make_box_problem<3>(spec));
}

TEST(GalerkinBandRows, EqualTheProbedProductOnAnEmbeddedBall) {
  expect_terms_equal_probed_product(test::clamped_ball(12));
}

// The coarsest level with Galerkin band rows (LU) takes the misaligned clamp's slow mode away in
// a two-level cycle, as the probed diagnostic does (test_galerkin_coarsest.cpp): 16^3 box, clamp
// 3, nu 0.495, every-child Dirichlet rule.
TEST(GalerkinBandRows, CoarsestRowsFixTheMisalignedClampInTwoLevels) {
  BoxSpec spec;
  spec.cells = 16;
  spec.poisson_ratio = 0.495;
  spec.clamp_cells = 3;
  auto rate = [&](CoarseBandRows rows, double* first) {
    MultigridOptions options;
    options.max_levels = 2;
    options.coarse_dirichlet = CoarseDirichletRule::EVERY_CHILD;
    options.coarse_band_rows = rows;
    Multigrid<3, double> mg(make_box_problem<3>(spec), options);
    EXPECT_EQ(mg.levels(), 2);
    EXPECT_EQ(mg.level(1).galerkin_band_rows, rows != CoarseBandRows::REDISCRETIZED);
    const auto& r = mg.run_cycles(12).residuals;
    *first = r[1] / r[0];
    return std::pow(r.back() / r[r.size() - 5], 0.25);
  };
  double first_rediscretized = 0, first_galerkin = 0;
  const double rediscretized = rate(CoarseBandRows::REDISCRETIZED, &first_rediscretized);
  const double galerkin = rate(CoarseBandRows::GALERKIN_COARSEST, &first_galerkin);
  EXPECT_GT(rediscretized, 0.5);
  EXPECT_GT(first_rediscretized, 1.0);
  EXPECT_LT(galerkin, 0.4);
  EXPECT_LT(first_galerkin, 1.0);
}

// Galerkin rows on every coarse level of a three-level cycle (the smoothed level keeps its
// rediscretized rows next to Dirichlet cells): the 64^3 box with its clamp top between coarse
// faces (7 cells), nu 0.495, converges at 0.35 instead of 0.73.
TEST(GalerkinBandRows, EveryCoarseLevelHalvesTheMisalignedClampsRateInThreeLevels) {
  BoxSpec spec;
  spec.cells = 64;
  spec.poisson_ratio = 0.495;
  spec.clamp_cells = 7;
  auto rate = [&](CoarseBandRows rows, CoarseDirichletRule rule) {
    MultigridOptions options;
    options.coarse_dirichlet = rule;
    options.coarse_band_rows = rows;
    Multigrid<3, float> mg(make_box_problem<3>(spec), options);
    EXPECT_EQ(mg.levels(), 3);
    for (int l = 1; l < mg.levels(); ++l)
      EXPECT_EQ(mg.level(l).galerkin_band_rows, rows == CoarseBandRows::GALERKIN);
    const auto& r = mg.run_cycles(10).residuals;
    return std::pow(r.back() / r[r.size() - 4], 1.0 / 3.0);
  };
  EXPECT_GT(rate(CoarseBandRows::REDISCRETIZED, CoarseDirichletRule::ANY_CHILD), 0.6);
  EXPECT_LT(rate(CoarseBandRows::GALERKIN, CoarseDirichletRule::EVERY_CHILD), 0.45);
}

TEST(GalerkinBandRows, UnknownNameIsRefusedNamingTheOption) {
  EXPECT_EQ(coarse_band_rows("galerkin", "x"), CoarseBandRows::GALERKIN);
  try {
    coarse_band_rows("galerkn", "--coarse-band-rows");
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("--coarse-band-rows"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("galerkn"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace mgelastic::grid
