#include <gtest/gtest.h>

#include <cmath>

#include "grid_test_support.hpp"
#include "mgelastic/grid/multigrid.hpp"

namespace mgelastic::grid {
namespace {

// Max error of u at interior variables after solving the discrete problem to 1e-11.
template <int Dim>
double max_error(int n, double poisson, bool traction) {
  const Material material{1e4, poisson};
  const test::PlaneWaveSolution<Dim> exact(material);
  // Dirichlet walls all around, or (traction) only the slab x < 1/8 with exact tractions.
  auto problem = test::unit_box<Dim>(n, material, [&](const IVec<Dim>& s) {
    if (traction) return s[0] <= n / 8;
    for (int a = 0; a < Dim; ++a)
      if (s[a] == 1 || s[a] == n) return true;
    return false;
  });
  problem.body_force = [&](const Vec<Dim>& x) { return exact.body_force(x); };
  problem.dirichlet_displacement = [&](const Vec<Dim>& x) { return exact.displacement(x); };
  if (traction)
    problem.boundary_stress = [&](int i, int j, const Vec<Dim>& x) {
      return exact.stress(i, j, x);
    };
  Multigrid<Dim, double> mg(problem);
  EXPECT_TRUE(mg.solve(1e-11, 60).converged);
  const auto& level = mg.finest();
  double error = 0;
  for (int i = 0; i < Dim; ++i) {
    for (std::size_t k = 0; k < level.size(); ++k) {
      if (level.kind(i, k) != VarKind::INTERIOR) continue;
      const double u = exact.displacement(level.lattice.face_center(i, k))[i];
      error = std::max(error, std::abs(level.x[i][k] - u));
    }
  }
  return error;
}

double order(double coarse_error, double fine_error) {
  return std::log2(coarse_error / fine_error);
}

// Grid-aligned Dirichlet boundaries: the staggered scheme is second order (>= 1.8).
TEST(ManufacturedSolution, SecondOrderWithAlignedDirichletBoundaries2D) {
  for (double nu : {0.3, 0.49}) {
    const double e32 = max_error<2>(32, nu, false), e64 = max_error<2>(64, nu, false);
    EXPECT_GE(order(e32, e64), 1.8) << "nu = " << nu << " errors " << e32 << " " << e64;
  }
}

TEST(ManufacturedSolution, SecondOrderWithAlignedDirichletBoundaries3D) {
  const double e8 = max_error<3>(8, 0.3, false), e16 = max_error<3>(16, 0.3, false);
  EXPECT_GE(order(e8, e16), 1.8) << "errors " << e8 << " " << e16;
}

// Traction boundaries: normal stresses sit half a cell inside, so first order (>= 0.9; the
// paper reports 1.15-1.25 for its embedded disc).
TEST(ManufacturedSolution, FirstOrderWithTractionBoundaries2D) {
  for (double nu : {0.3, 0.49}) {
    const double e32 = max_error<2>(32, nu, true), e64 = max_error<2>(64, nu, true);
    EXPECT_GE(order(e32, e64), 0.9) << "nu = " << nu << " errors " << e32 << " " << e64;
  }
}

TEST(ManufacturedSolution, FirstOrderWithTractionBoundaries3D) {
  const double e16 = max_error<3>(16, 0.3, true), e32 = max_error<3>(32, 0.3, true);
  EXPECT_GE(order(e16, e32), 0.9) << "errors " << e16 << " " << e32;
}

}  // namespace
}  // namespace mgelastic::grid
