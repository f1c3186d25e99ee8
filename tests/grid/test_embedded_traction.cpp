#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "grid_test_support.hpp"
#include "mgelastic/grid/disc_study.hpp"
#include "mgelastic/grid/embedded_traction.hpp"
#include "mgelastic/grid/explicit_rows.hpp"
#include "mgelastic/grid/level.hpp"
#include "mgelastic/grid/multigrid.hpp"
#include "support/tolerances.hpp"

namespace mgelastic::grid {
namespace {

// Surface forces of the exact traction on the box faces x = 1, y = 0, y = 1 (polygon of 8n
// segments per face, half of each segment force to each end point).
std::vector<SurfaceForce<2>> box_face_forces(int n, const test::PlaneWaveSolution<2>& exact) {
  std::vector<SurfaceForce<2>> forces;
  auto add_line = [&](const Vec<2>& from, const Vec<2>& to, const Vec<2>& normal) {
    const int segments = 8 * n;
    for (int k = 0; k < segments; ++k) {
      const Vec<2> a = from + (to - from) * double(k) / segments;
      const Vec<2> b = from + (to - from) * double(k + 1) / segments;
      const Vec<2> mid = 0.5 * (a + b);
      Vec<2> t;
      for (int i = 0; i < 2; ++i)
        t[i] = exact.stress(i, 0, mid) * normal[0] + exact.stress(i, 1, mid) * normal[1];
      forces.push_back({a, 0.5 * (b - a).norm() * t, normal});
      forces.push_back({b, 0.5 * (b - a).norm() * t, normal});
    }
  };
  add_line({0.125, 0.0}, {1.0, 0.0}, {0.0, -1.0});
  add_line({1.0, 0.0}, {1.0, 1.0}, {1.0, 0.0});
  add_line({0.125, 1.0}, {1.0, 1.0}, {0.0, 1.0});
  return forces;
}

double box_error(int n) {
  const Material material{1e4, 0.3};
  const test::PlaneWaveSolution<2> exact(material);
  auto problem = test::unit_box<2>(n, material, [&](const IVec<2>& s) { return s[0] <= n / 8; });
  problem.body_force = [&](const Vec<2>& x) { return exact.body_force(x); };
  problem.dirichlet_displacement = [&](const Vec<2>& x) { return exact.displacement(x); };
  apply_surface_forces(problem, box_face_forces(n, exact));
  Multigrid<2, double> mg(problem);
  EXPECT_TRUE(mg.solve(1e-11, 60).converged);
  double error = 0;
  const auto& level = mg.finest();
  for (int i = 0; i < 2; ++i)
    for (std::size_t k = 0; k < level.size(); ++k)
      if (level.kind(i, k) == VarKind::INTERIOR)
        error = std::max(error, std::abs(mg.solution(i, k) -
                                         exact.displacement(level.lattice.face_center(i, k))[i]));
  return error;
}

// Sec. 9.2 on grid-aligned traction faces: the distributed surface forces reproduce the
// traction boundary condition with first-order accuracy.
TEST(EmbeddedTraction, SurfaceForcesOnAlignedFacesConvergeFirstOrder) {
  // Observed 1.02 (32 -> 64) and 1.01 (64 -> 128); 0.90-0.91 while shares on inactive faces at
  // the box corners were dropped. The margin allows for round-off in the quantized stress
  // locations.
  const double e64 = box_error(64), e128 = box_error(128);
  EXPECT_GE(std::log2(e64 / e128), 0.95) << e64 << " " << e128;
}

// The distribution conserves force: interior densities times cell volume plus eliminated
// stresses times face area add up to the applied force (checked through the right-hand side:
// a uniform horizontal force on a vertical line inside one interior cell row).
TEST(EmbeddedTraction, InteriorForcesBecomeDensities) {
  auto problem = test::unit_box<2>(8, {1.0, 0.3}, [](const IVec<2>& s) { return s[0] == 1; });
  apply_surface_forces<2>(problem, {{Vec<2>(0.5, 0.5), Vec<2>(2.0, -1.0), Vec<2>(1.0, 0.0)}});
  double total_x = 0, total_y = 0;
  const double cell_volume = problem.lattice.h * problem.lattice.h;
  for (const auto& load : problem.variable_loads)
    (load.component == 0 ? total_x : total_y) += load.density * cell_volume;
  EXPECT_NEAR(total_x, 2.0, 1e-12);
  EXPECT_NEAR(total_y, -1.0, 1e-12);
}

// A ball of radius 0.3 (cells overlapping it are interior, no Dirichlet cells) with point forces
// at points of its sphere; returns the force the interior momentum rows see, i.e. the sum over
// interior u_i rows of (boundary-stress constant + load density) * h^d, which telescopes to the
// boundary force of the discrete system, and the applied total in `applied`.
template <int Dim>
Vec<Dim> force_on_rows(int n, Vec<Dim>& applied) {
  ElasticityProblem<Dim> problem;
  problem.lattice = Lattice<Dim>(IVec<Dim>::Constant(n), 1.0 / n);
  problem.material = {1.0, 0.3};
  problem.cells.assign(problem.lattice.size(), CellType::EXTERIOR);
  const Vec<Dim> center = Vec<Dim>::Constant(0.5);
  const double radius = 0.3, h = problem.lattice.h;
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(problem.lattice.size()); ++k) {
    if (!problem.lattice.is_real(problem.lattice.coords(k))) continue;
    const Vec<Dim> lo = problem.lattice.cell_center(k) - Vec<Dim>::Constant(0.5 * h);
    const Vec<Dim> nearest = center.cwiseMax(lo).cwiseMin(lo + Vec<Dim>::Constant(h));
    if ((nearest - center).norm() < radius) problem.cells[k] = CellType::INTERIOR;
  }
  // Points on the sphere from a seeded generator, forces of both signs in every component.
  std::mt19937 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<SurfaceForce<Dim>> forces;
  applied = Vec<Dim>::Zero();
  for (int k = 0; k < 40 * n; ++k) {
    Vec<Dim> direction, force;
    for (int a = 0; a < Dim; ++a) direction[a] = normal(rng), force[a] = normal(rng) / n;
    direction.normalize();
    forces.push_back({Vec<Dim>(center + radius * direction), force, direction});
    applied += force;
  }
  apply_surface_forces(problem, forces);
  const auto level = build_level<Dim, double>(problem.lattice, problem.cells, problem.material,
                                              problem.boundary_stress, nullptr);
  const RowBuilder<Dim> rows(problem.lattice, problem.cells, problem.material.mu(),
                             problem.boundary_stress);
  const double volume = std::pow(h, Dim);
  Vec<Dim> total = Vec<Dim>::Zero();
  for (int i = 0; i < Dim; ++i)
    for (std::size_t k = 0; k < level.size(); ++k)
      if (level.kind(i, k) == VarKind::INTERIOR) total[i] += rows.momentum(i, k).constant * volume;
  for (const auto& load : problem.variable_loads) total[load.component] += load.density * volume;
  return total;
}

// Force conservation on a curved staircase (Sec. 9.2): every share of every point force reaches
// an interior row, also at staircase corners where some bilinear corners are inactive faces.
TEST(EmbeddedTraction, ForceOnCurvedStaircaseIsConserved2D) {
  for (int n : {32, 64}) {
    Vec<2> applied;
    const Vec<2> seen = force_on_rows<2>(n, applied);
    // Sums of a few thousand terms: round-off relative to the largest component.
    EXPECT_LE((seen - applied).norm(), mgelastic::test::kStencilRoundoff * applied.norm())
        << "n = " << n;
  }
}

TEST(EmbeddedTraction, ForceOnCurvedStaircaseIsConserved3D) {
  Vec<3> applied;
  const Vec<3> seen = force_on_rows<3>(16, applied);
  EXPECT_LE((seen - applied).norm(), mgelastic::test::kStencilRoundoff * applied.norm());
}

// The paper's disc study (Sec. 9.2): embedded traction on two quadrants, Dirichlet on two,
// errors decrease at first order for compressible and near-incompressible material. The
// constant of the O(h) error depends erratically on how the lattice cuts the circle (n * error
// ranges 0.99-1.19 for nu = 0.2 over n = 128 ... 2048), so the order of one doubling scatters
// around 1 (0.93-0.95 for 128 -> 256); 256 -> 512 is the finest pair that runs in seconds and
// the pair `mgelastic bench disc-accuracy` reports (1.03 and 1.05, docs/grid-engine.md).
TEST(DiscStudy, EmbeddedDiscConvergesAtFirstOrder) {
  for (double nu : {0.2, 0.49}) {
    const DiscStudy study = run_disc_study(nu, {256, 512});
    EXPECT_GE(study.order, 1.0) << "nu = " << nu;
  }
}

}  // namespace
}  // namespace mgelastic::grid
