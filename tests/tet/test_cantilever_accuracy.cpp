// Accuracy: clamped cantilever under gravity against Euler-Bernoulli / Timoshenko beam theory.
//
// Beam: length L = 1 along x, square cross-section b = h = 0.1, clamped at x = 0 (all vertices
// of that face fixed), gravity along -y, E = 1e9, nu = 0.3, rho = 1000. Tip deflection (mean over
// the vertices of the free end face) from a corotated static solve on regular tet grids with 2, 4
// and 6 cells across the thickness (sparse Cholesky; a few seconds in Release).
//   Euler-Bernoulli:  w = q L^4 / (8 E I),  q = rho g b h,  I = b h^3 / 12   (= 1.4715e-3)
//   Timoshenko adds   q L^2 / (2 kappa G A),  kappa = 10 (1 + nu) / (12 + 11 nu)   (+1.2%)
// Linear tetrahedra lock in bending, so the deflection approaches from below.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "mgelastic/tet/corotated_solver.hpp"
#include "tet/tet_test_support.hpp"

namespace mgelastic::tet {
namespace {

constexpr double kLength = 1.0, kThickness = 0.1, kE = 1e9, kNu = 0.3, kRho = 1000.0, kG = 9.81;

double euler_bernoulli() {
  const double q = kRho * kG * kThickness * kThickness;
  const double inertia = std::pow(kThickness, 4) / 12.0;
  return q * std::pow(kLength, 4) / (8.0 * kE * inertia);
}

double timoshenko() {
  const double q = kRho * kG * kThickness * kThickness;
  const double kappa = 10.0 * (1.0 + kNu) / (12.0 + 11.0 * kNu);
  const double shear = kE / (2.0 * (1.0 + kNu));
  return euler_bernoulli() +
         q * kLength * kLength / (2.0 * kappa * shear * kThickness * kThickness);
}

double tip_deflection(int cells_across, double poisson_ratio, int& tets) {
  const geometry::TetMesh mesh =
      test::box_mesh(Eigen::Vector3d(kLength, kThickness, kThickness), kThickness / cells_across);
  tets = mesh.tet_count();
  CorotatedSolverSettings settings;
  settings.gravity = Eigen::Vector3d(0, -kG, 0);
  settings.linear_solver = LinearSolver::CHOLESKY;
  CorotatedSolver solver(
      mesh, ElementMaterials::uniform(mesh.tet_count(), {kE, poisson_ratio, kRho}), settings);
  std::vector<int> clamped, tip;
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    if (mesh.vertices(v, 0) < 1e-9) clamped.push_back(v);
    if (mesh.vertices(v, 0) > kLength - 1e-9) tip.push_back(v);
  }
  solver.set_dirichlet(clamped);
  solver.solve_static(20, 1e-8);
  double sum = 0.0;
  for (int v : tip) sum += solver.positions()[3 * v + 1] - mesh.vertices(v, 1);
  return -sum / static_cast<double>(tip.size());
}

// Cells across the thickness: 2, 4, 6 by default; MGELASTIC_CANTILEVER_FINE=1 appends 8, 12 and
// 16 (30k, 100k and 246k tets; the 16 cell solve factorizes a 140k-unknown system a few times,
// minutes and a few GB) for the documented table.
std::vector<int> refinements() {
  std::vector<int> cells = {2, 4, 6};
  const char* fine = std::getenv("MGELASTIC_CANTILEVER_FINE");
  if (fine != nullptr && std::string(fine) == "1") cells.insert(cells.end(), {8, 12, 16});
  return cells;
}

TEST(CantileverAccuracy, TipDeflectionConvergesToBeamTheory) {
  std::vector<double> deflections;
  for (int cells : refinements()) {
    int tets = 0;
    deflections.push_back(tip_deflection(cells, kNu, tets));
    std::printf(
        "[cantilever nu=0.3] %d cells across, %6d tets: tip %.6e  / EB %.4f  / Timoshenko %.4f\n",
        cells, tets, deflections.back(), deflections.back() / euler_bernoulli(),
        deflections.back() / timoshenko());
  }
  // Monotone convergence from below (locking decreases with refinement).
  for (std::size_t i = 1; i < deflections.size(); ++i)
    EXPECT_LT(deflections[i - 1], deflections[i]);
  EXPECT_LT(deflections.back(), 1.01 * timoshenko());
  // Observed order ~1.6 in h: the error must at least halve from 2 to 4 cells and keep falling.
  const double t = timoshenko();
  EXPECT_LT(t - deflections[1], 0.5 * (t - deflections[0]));
  // 6 cells across (13k tets, ~1 s) is the finest size in the default run: 12% below
  // Timoshenko. The 3% needs 16 cells (246k tets); see docs/tet-engine.md.
  EXPECT_GT(deflections[2], 0.85 * t);
  if (deflections.size() > 5) {
    EXPECT_GT(deflections[4], 0.95 * t);
    // The target: within 3 % of Timoshenko at the finest mesh (16 cells across).
    EXPECT_GT(deflections[5], 0.97 * t);
  }
}

TEST(CantileverAccuracy, ReportsLockingAtNearIncompressibility) {
  // Linear tets lock as nu -> 0.5 (volumetric constraints at every element); the ratios are
  // reported for the docs, the test only checks that the solves stay finite and sag downwards.
  for (double nu : {0.45, 0.49}) {
    int tets = 0;
    const double w = tip_deflection(4, nu, tets);
    std::printf("[cantilever nu=%.2f] 4 cells across, %d tets: tip / EB = %.4f\n", nu, tets,
                w / euler_bernoulli());
    EXPECT_TRUE(std::isfinite(w));
    EXPECT_GT(w, 0.0);
  }
}

}  // namespace
}  // namespace mgelastic::tet
