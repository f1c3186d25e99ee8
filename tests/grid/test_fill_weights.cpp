// Fill weights of coarse cells (grid/fill_weights.hpp): they count the fine body volume, keep the
// weighted coarse system symmetric positive definite, and restore the coarse stiffness of thin
// parts, which the unweighted coarse operator of Sec. 6 overestimates.
#include <gtest/gtest.h>

#include <Eigen/SparseCholesky>
#include <cstdio>
#include <functional>

#include "mgelastic/grid/coarsening.hpp"
#include "mgelastic/grid/convergence_rate.hpp"
#include "mgelastic/grid/fill_weights.hpp"
#include "mgelastic/grid/multigrid.hpp"
#include "mgelastic/grid/nonaugmented_system.hpp"

namespace mgelastic::grid {
namespace {

// n cells per axis, h = 1/16; cells where `body(s)` holds are interior, those of them with
// s_x == 1 Dirichlet; gravity along -z.
ElasticityProblem<3> typed_problem(const IVec<3>& n,
                                   const std::function<bool(const IVec<3>&)>& body) {
  ElasticityProblem<3> problem;
  problem.lattice = Lattice<3>(n, 1.0 / 16);
  problem.material = {1e5, 0.45};
  problem.cells.assign(problem.lattice.size(), CellType::EXTERIOR);
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(problem.lattice.size()); ++k) {
    const IVec<3> s = problem.lattice.coords(k);
    if (!problem.lattice.is_real(s) || !body(s)) continue;
    problem.cells[k] = s[0] == 1 ? CellType::DIRICHLET : CellType::INTERIOR;
  }
  problem.body_force = [](const Vec<3>&) { return Vec<3>(0, 0, -1e3); };
  return problem;
}

// A cantilever plate `thickness` cells thick, clamped at x = 1.
ElasticityProblem<3> plate(int thickness) {
  return typed_problem(IVec<3>(24, 12, 8),
                       [thickness](const IVec<3>& s) { return s[2] >= 2 && s[2] < 2 + thickness; });
}

double max_abs(Eigen::SparseMatrix<double> m) {
  m.makeCompressed();
  return m.nonZeros() == 0 ? 0.0 : m.coeffs().cwiseAbs().maxCoeff();
}

double body_cells(const std::vector<CellType>& cells) {
  double count = 0;
  for (CellType c : cells) count += c != CellType::EXTERIOR ? 1 : 0;
  return count;
}

TEST(FillWeights, CoarseWeightsCountTheFineBodyVolume) {
  // An odd-sized ball-like body: partly filled coarse cells on every level.
  const ElasticityProblem<3> problem = typed_problem(IVec<3>(13, 11, 9), [](const IVec<3>& s) {
    return (s.cast<double>() - Vec<3>(7, 6, 5)).squaredNorm() < 20.0;
  });
  std::vector<double> weights;
  Lattice<3> lattice = problem.lattice;
  std::vector<CellType> cells = problem.cells;
  double scale = 1;
  for (int level = 1; level <= 2; ++level) {
    const Lattice<3> coarse = coarsen(lattice);
    const std::vector<CellType> coarse_cells = coarsen_cells(lattice, cells);
    weights = coarse_fill_weights(lattice, cells, weights, coarse, coarse_cells);
    scale *= 8;
    double volume = 0, lightest = 1;
    for (std::size_t c = 0; c < weights.size(); ++c) {
      volume += scale * weights[c];
      if (coarse_cells[c] == CellType::INTERIOR) lightest = std::min(lightest, weights[c]);
    }
    EXPECT_NEAR(volume, body_cells(problem.cells), 1e-9) << "level " << level;
    EXPECT_LT(lightest, 0.5) << "level " << level;
    EXPECT_GT(lightest, 0.0) << "level " << level;
    lattice = coarse;
    cells = coarse_cells;
  }
}

TEST(FillWeights, WeightedCoarseSystemIsSymmetricPositiveDefinite) {
  const ElasticityProblem<3> problem = plate(3);
  const Lattice<3> coarse = coarsen(problem.lattice);
  const std::vector<CellType> coarse_cells = coarsen_cells(problem.lattice, problem.cells);
  const std::vector<double> weights =
      coarse_fill_weights(problem.lattice, problem.cells, {}, coarse, coarse_cells);
  ASSERT_FALSE(all_full(weights, coarse_cells));  // the plate's top coarse layer is half full
  const auto level =
      build_level<3, double>(coarse, coarse_cells, problem.material, {}, nullptr, 0.0, 0, weights);
  const auto system = assemble_nonaugmented(level, BoundaryStress<3>{});
  const Eigen::SparseMatrix<double> asymmetry =
      system.matrix - Eigen::SparseMatrix<double>(system.matrix.transpose());
  EXPECT_LT(max_abs(asymmetry), 1e-12 * max_abs(system.matrix));
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>> cholesky(system.matrix);
  EXPECT_EQ(cholesky.info(), Eigen::Success);
  // Weights of one everywhere give the unweighted system exactly.
  std::vector<double> ones(weights.size(), 1.0);
  const auto full =
      build_level<3, double>(coarse, coarse_cells, problem.material, {}, nullptr, 0.0, 0, ones);
  const auto plain = build_level<3, double>(coarse, coarse_cells, problem.material, {}, nullptr);
  const Eigen::SparseMatrix<double> difference =
      assemble_nonaugmented(full, BoundaryStress<3>{}).matrix -
      assemble_nonaugmented(plain, BoundaryStress<3>{}).matrix;
  EXPECT_EQ(max_abs(difference), 0.0);
}

// An odd thickness coarsens into a plate one fine cell thicker (3 -> 4: bending stiffness
// (4/3)^3 = 2.4 times too high, 5 -> 6: 1.7 times); the weights bring the V-cycle rate down.
TEST(FillWeights, ThinPlatesConvergeFasterWithWeights) {
  for (int thickness : {3, 5}) {
    double rate[2];
    for (bool weighted : {false, true}) {
      Multigrid<3, double> mg(plate(thickness), {.coarse_fill_weights = weighted});
      rate[weighted] = convergence_rate(mg.run_cycles(25).residuals, 1e-11);
    }
    std::printf("plate %d cells thick: V-cycle rate %.3f unweighted, %.3f weighted\n", thickness,
                rate[0], rate[1]);
    RecordProperty("rate_unweighted_" + std::to_string(thickness), std::to_string(rate[0]));
    RecordProperty("rate_weighted_" + std::to_string(thickness), std::to_string(rate[1]));
    EXPECT_LT(rate[1], rate[0]) << thickness;
  }
}

}  // namespace
}  // namespace mgelastic::grid
