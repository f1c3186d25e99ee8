// Loads replaced without a hierarchy build (load_update.hpp, Multigrid::set_loads, issue 21):
// a level, a hierarchy or a backward-Euler integrator built with load A and given load B holds,
// computes and converges to what one built with load B does.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "grid_test_support.hpp"
#include "mgelastic/core/error.hpp"
#include "mgelastic/grid/backward_euler.hpp"
#include "mgelastic/grid/box_problem.hpp"
#include "mgelastic/grid/embedded_traction.hpp"
#include "mgelastic/grid/level.hpp"
#include "mgelastic/grid/load_update.hpp"
#include "mgelastic/grid/multigrid.hpp"

namespace mgelastic::grid {
namespace {

// Non-zero on every traction face and edge, varying in space and per (i, j), so that a value
// taken at the wrong point or for the wrong component shows.
template <int Dim>
BoundaryStress<Dim> varying_stress(double scale) {
  return [scale](int i, int j, const Vec<Dim>& x) {
    return i == j ? scale * (40.0 + 25.0 * x[0] - 10.0 * x[1] + 7.0 * i)
                  : scale * (15.0 * x[1] - 5.0 * j + 3.0 * i + 2.0);
  };
}

template <int Dim, typename Scalar>
void expect_same_stress_values(const Level<Dim, Scalar>& a, const Level<Dim, Scalar>& b) {
  EXPECT_EQ(a.band_kernel.constant, b.band_kernel.constant);
  EXPECT_EQ(a.band_u.constant, b.band_u.constant);
  EXPECT_EQ(a.band_p.constant, b.band_p.constant);
  ASSERT_EQ(a.traction.normal.size(), b.traction.normal.size());
  for (std::size_t r = 0; r < a.traction.normal.size(); ++r)
    EXPECT_EQ(a.traction.normal[r].sigma, b.traction.normal[r].sigma) << "normal rule " << r;
  ASSERT_EQ(a.traction.thin.size(), b.traction.thin.size());
  for (std::size_t r = 0; r < a.traction.thin.size(); ++r)
    EXPECT_EQ(a.traction.thin[r].sigma, b.traction.thin[r].sigma) << "thin rule " << r;
  ASSERT_EQ(a.traction.shear.size(), b.traction.shear.size());
  for (std::size_t r = 0; r < a.traction.shear.size(); ++r) {
    const auto ca = a.traction.candidates(a.traction.shear[r]);
    const auto cb = b.traction.candidates(b.traction.shear[r]);
    ASSERT_EQ(ca.size(), cb.size());
    for (std::size_t c = 0; c < ca.size(); ++c)
      EXPECT_EQ(ca[c].sigma_term, cb[c].sigma_term) << "shear rule " << r << " candidate " << c;
  }
}

template <int Dim, typename Scalar>
Level<Dim, Scalar> level_with(const ElasticityProblem<Dim>& problem,
                              const BoundaryStress<Dim>& sigma) {
  return build_level<Dim, Scalar>(problem.lattice, problem.cells, problem.material, sigma, nullptr,
                                  problem.inertia);
}

template <int Dim, typename Scalar>
void check_replaced_stresses(unsigned seed) {
  auto problem = test::irregular_problem<Dim>(10, seed, Material{1e4, 0.35});
  problem.inertia = 50.0;
  const auto a = varying_stress<Dim>(1.0), b = varying_stress<Dim>(-2.5);
  Level<Dim, Scalar> replaced = level_with<Dim, Scalar>(problem, a);
  const Level<Dim, Scalar> fresh = level_with<Dim, Scalar>(problem, b);
  // The geometry has every kind of rule, and load A's values differ from B's.
  ASSERT_FALSE(fresh.traction.thin.empty());
  ASSERT_FALSE(fresh.traction.shear.empty());
  ASSERT_FALSE(fresh.band_p.rows() == 0);
  ASSERT_NE(replaced.band_kernel.constant, fresh.band_kernel.constant);
  replace_boundary_stress(replaced, b);
  expect_same_stress_values(replaced, fresh);
  // Back to zero traction: every value vanishes as in a build without stresses.
  replace_boundary_stress(replaced, BoundaryStress<Dim>{});
  expect_same_stress_values(replaced, level_with<Dim, Scalar>(problem, {}));
}

TEST(LoadUpdate, ReplacedStressesEqualThoseOfALevelBuiltWithThem) {
  for (const unsigned seed : {3u, 11u}) {
    check_replaced_stresses<2, double>(seed);
    check_replaced_stresses<2, float>(seed);
    check_replaced_stresses<3, double>(seed);
    check_replaced_stresses<3, float>(seed);
  }
}

// The box cantilever (Dirichlet slab at x < 1/8) under load A or B: body force, a varying
// boundary stress on all traction faces, and surface point forces (variable loads and stress
// table entries, Sec. 9.2).
ElasticityProblem<3> cantilever(bool load_b, double inertia) {
  auto problem = make_box_problem<3>({.cells = 16, .poisson_ratio = 0.3, .body_force = 1e3});
  problem.inertia = inertia;
  const Vec<3> g = load_b ? Vec<3>(800.0, 300.0, -1500.0) : Vec<3>(0.0, -1e3, 0.0);
  problem.body_force = [g](const Vec<3>&) { return g; };
  problem.boundary_stress = varying_stress<3>(load_b ? -30.0 : 10.0);
  std::vector<SurfaceForce<3>> forces;
  if (load_b) {
    forces.push_back({Vec<3>(1.0, 0.37, 0.61), Vec<3>(0.0, -4.0, 1.0), Vec<3>(1.0, 0.0, 0.0)});
    forces.push_back({Vec<3>(0.53, 1.0, 0.29), Vec<3>(2.0, 3.0, 0.0), Vec<3>(0.0, 1.0, 0.0)});
  } else {
    forces.push_back({Vec<3>(0.71, 0.44, 1.0), Vec<3>(0.0, 0.0, -6.0), Vec<3>(0.0, 0.0, 1.0)});
  }
  apply_surface_forces(problem, forces);
  return problem;
}

template <typename Scalar>
double max_difference(const Multigrid<3, Scalar>& a, const Multigrid<3, Scalar>& b, double& scale) {
  const auto& xa = a.solution_state();
  const auto& xb = b.solution_state();
  double difference = 0;
  scale = 0;
  for (int f = 0; f < 3; ++f)  // displacements
    for (std::size_t k = 0; k < xa[f].size(); ++k) {
      difference = std::max(difference, std::abs(xa[f][k] - xb[f][k]));
      scale = std::max(scale, std::abs(xb[f][k]));
    }
  return difference;
}

struct Case {
  bool mixed_precision;
  double inertia;
  double tolerance;  // relative residual of both solves
  double agreement;  // relative difference of the solutions
};

template <typename Scalar>
void check_set_loads(const Case& c) {
  MultigridOptions options;
  options.mixed_precision = c.mixed_precision;
  Multigrid<3, Scalar> replaced(cantilever(false, c.inertia), options);
  replaced.solve(c.tolerance, 60);  // load A's solution: the warm start for load B
  const ElasticityProblem<3> b = cantilever(true, c.inertia);
  replaced.set_loads(b);

  // Right after set_loads: the residual of a hierarchy built with B at the same x.
  Multigrid<3, Scalar> same_x(b, options);
  same_x.set_solution_state(replaced.solution_state());
  const double residual = replaced.residual();
  EXPECT_NEAR(residual, same_x.residual(), 1e-12 * residual);
  Multigrid<3, Scalar> fresh_a(cantilever(false, c.inertia), options);
  fresh_a.set_solution_state(replaced.solution_state());
  EXPECT_GT(std::abs(fresh_a.residual() - residual), 1e-3 * residual);  // A's would differ

  const SolveReport report = replaced.solve(c.tolerance, 80);
  EXPECT_TRUE(report.converged);
  Multigrid<3, Scalar> fresh(b, options);
  EXPECT_TRUE(fresh.solve(c.tolerance, 80).converged);
  double scale = 0;
  const double difference = max_difference(replaced, fresh, scale);
  EXPECT_GT(scale, 0.0);
  EXPECT_LE(difference, c.agreement * scale) << difference << " of " << scale;
}

TEST(LoadUpdate, SetLoadsSolvesAsAFreshBuildInDouble) {
  check_set_loads<double>(
      {.mixed_precision = true, .inertia = 0.0, .tolerance = 1e-11, .agreement = 1e-9});
  check_set_loads<double>(
      {.mixed_precision = true, .inertia = 2e5, .tolerance = 1e-11, .agreement = 1e-9});
}

TEST(LoadUpdate, SetLoadsSolvesAsAFreshBuildInMixedPrecision) {
  check_set_loads<float>(
      {.mixed_precision = true, .inertia = 0.0, .tolerance = 1e-11, .agreement = 1e-9});
  check_set_loads<float>(
      {.mixed_precision = true, .inertia = 2e5, .tolerance = 1e-11, .agreement = 1e-9});
}

// Single precision: the loads live on the float finest level itself (no solution level).
TEST(LoadUpdate, SetLoadsSolvesAsAFreshBuildInSinglePrecision) {
  check_set_loads<float>(
      {.mixed_precision = false, .inertia = 0.0, .tolerance = 1e-5, .agreement = 1e-4});
}

TEST(LoadUpdate, SetLoadsRefusesAnotherSystem) {
  Multigrid<3, double> mg(cantilever(false, 0.0));
  auto other = cantilever(true, 0.0);
  other.material = {2e5, 0.3};
  EXPECT_THROW(mg.set_loads(other), Error);
  other = cantilever(true, 0.0);
  other.cells[other.lattice.index(IVec<3>(8, 8, 8))] = CellType::EXTERIOR;
  EXPECT_THROW(mg.set_loads(other), Error);
  other = cantilever(true, 0.0);
  other.variable_loads.push_back({.component = 0, .face = -1, .density = 1.0});
  EXPECT_THROW(mg.set_loads(other), Error);
}

// Backward Euler: a step under new loads continues exactly as an integrator built with them
// from the same state (displacement, velocity), so the step's b is rebuilt from the new loads.
template <typename Scalar>
void check_dynamic_set_loads() {
  const TimeStepOptions options{.dt = 0.01,
                                .density = 1000.0,
                                .damping = 0.002,
                                .vcycles_per_step = 0,
                                .tolerance = 1e-11,
                                .max_vcycles = 80};
  BackwardEuler<3, Scalar> replaced(cantilever(false, 0.0), options);
  replaced.step();
  replaced.step();
  replaced.set_loads(cantilever(true, 0.0));
  BackwardEuler<3, Scalar> fresh(cantilever(true, 0.0), options);
  fresh.multigrid().set_solution_state(replaced.multigrid().solution_state());
  fresh.velocity() = replaced.velocity();
  EXPECT_TRUE(replaced.step().converged);
  EXPECT_TRUE(fresh.step().converged);
  double scale = 0;
  const double difference = max_difference(replaced.multigrid(), fresh.multigrid(), scale);
  EXPECT_GT(scale, 0.0);
  EXPECT_LE(difference, 1e-9 * scale) << difference << " of " << scale;
}

TEST(LoadUpdate, BackwardEulerStepUnderNewLoadsEqualsAFreshIntegrator) {
  check_dynamic_set_loads<double>();
  check_dynamic_set_loads<float>();
}

}  // namespace
}  // namespace mgelastic::grid
