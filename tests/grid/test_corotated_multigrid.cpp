// Co-rotational linear elasticity (Sec. 7): the quasi-linear operator (14) with frozen rotations,
// the outer iteration refreshing them, and its invariance under large rigid rotations.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>

#include "dynamics_test_support.hpp"
#include "grid_test_support.hpp"
#include "mgelastic/core/threads.hpp"
#include "mgelastic/grid/corotated_dynamics.hpp"
#include "mgelastic/grid/corotated_multigrid.hpp"
#include "mgelastic/grid/multigrid.hpp"

namespace mgelastic::grid {
namespace {

using Field = std::function<Vec<3>(const Vec<3>&)>;
using test::corotated_energy;

using test::end_clamped_bar;

// Largest |u - expected| over the interior and Dirichlet faces of the finest level.
double max_face_error(const Level<3, double>& level, const Field& expected) {
  double worst = 0;
  for (int i = 0; i < 3; ++i)
    for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(level.size()); ++k) {
      const VarKind kind = level.kind(i, k);
      if (kind != VarKind::INTERIOR && kind != VarKind::DIRICHLET) continue;
      worst =
          std::max(worst, std::abs(level.x[i][k] - expected(level.lattice.face_center(i, k))[i]));
    }
  return worst;
}

bool all_finite(const Level<3, double>& level) {
  for (const auto& field : level.x)
    for (double v : field)
      if (!std::isfinite(v)) return false;
  return true;
}

// Geometric mean of the per-cycle reduction over the whole history.
double mean_rate(const std::vector<double>& residuals) {
  const int cycles = static_cast<int>(residuals.size()) - 1;
  return std::pow(residuals.back() / residuals.front(), 1.0 / cycles);
}

TEST(CorotatedMultigrid, BarWithEndsRotatedByNinetyDegreesReachesTheRotatedRestShape) {
  ElasticityProblem<3> problem = end_clamped_bar(16, 0.3, false);
  const Vec<3> center(0.5, 0.125, 0.125);
  const Matrix<3> rotation = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).matrix();
  const Field rigid = [&](const Vec<3>& x) -> Vec<3> {
    return (rotation - Matrix<3>::Identity()) * (x - center);
  };
  problem.dirichlet_displacement = rigid;

  CorotatedOptions options;
  options.rotation_update_every = 1;  // cold start far from the solution: refresh every cycle
  CorotatedMultigrid<3> corotated(problem, {}, options);
  const CorotatedReport report = corotated.solve(1e-6, 200);
  const double corotated_error = max_face_error(corotated.solution_level(), rigid);
  const double corotated_energy_value =
      corotated_energy(corotated.solution_level(), problem.material);

  Multigrid<3, double> linear(problem);
  linear.solve(1e-10, 100);
  const double linear_error = max_face_error(linear.solution_level(), rigid);
  const double linear_energy_value = corotated_energy(linear.solution_level(), problem.material);
  std::printf(
      "90-degree rigid end rotation, bar length 1: max |u - u_rigid| corotated %.3g (%d cycles, "
      "non-linear residual %.3g -> %.3g), linear %.3g; co-rotated energy: corotated %.3g, "
      "linear %.3g\n",
      corotated_error, report.cycles(), report.nonlinear.front(), report.nonlinear.back(),
      linear_error, corotated_energy_value, linear_energy_value);
  EXPECT_TRUE(report.converged);
  EXPECT_LT(corotated_error, 1e-3);
  EXPECT_LT(corotated_energy_value, 1e-8);
  EXPECT_GT(linear_error, 0.05);
  EXPECT_GT(linear_energy_value, 1e-3);
}

// A 8^3 box inside a shell of Dirichlet cells that carry the affine displacement A x.
ElasticityProblem<3> patch(const Matrix<3>& a, double nu) {
  ElasticityProblem<3> problem = test::unit_box<3>(10, Material{1.0, nu}, [](const IVec<3>& s) {
    return s.minCoeff() == 1 || s.maxCoeff() == 10;
  });
  problem.dirichlet_displacement = [a](const Vec<3>& x) -> Vec<3> { return a * x; };
  return problem;
}

void expect_affine_in_both_models(const Matrix<3>& a, const char* name) {
  const ElasticityProblem<3> problem = patch(a, 0.45);
  const Field affine = [a](const Vec<3>& x) -> Vec<3> { return a * x; };
  CorotatedMultigrid<3> corotated(problem);
  const CorotatedReport report = corotated.solve(1e-12, 60);
  Multigrid<3, double> linear(problem);
  linear.solve(1e-12, 60);
  const double corotated_error = max_face_error(corotated.solution_level(), affine);
  const double linear_error = max_face_error(linear.solution_level(), affine);
  std::printf("%s patch: max error corotated %.3g (%d cycles), linear %.3g\n", name,
              corotated_error, report.cycles(), linear_error);
  EXPECT_TRUE(report.converged);
  EXPECT_LT(corotated_error, 1e-9);
  EXPECT_LT(linear_error, 1e-9);
}

TEST(CorotatedMultigrid, UniformStretchIsReproducedExactlyInBothModels) {
  expect_affine_in_both_models(Eigen::Vector3d(0.02, -0.005, 0.01).asDiagonal(), "stretch");
}

TEST(CorotatedMultigrid, UniformShearIsReproducedExactlyInBothModels) {
  Matrix<3> shear = Matrix<3>::Zero();
  shear(0, 1) = 0.1;  // simple shear: F is not symmetric, R is a finite rotation
  expect_affine_in_both_models(shear, "shear");
}

TEST(CorotatedMultigrid, SmallDeformationsAgreeWithTheLinearModel) {
  ElasticityProblem<3> problem = end_clamped_bar(16, 0.4, true);
  problem.body_force = [](const Vec<3>&) { return Vec<3>(0, -1e-6, 0); };
  CorotatedMultigrid<3> corotated(problem);
  corotated.solve(1e-10, 60);
  Multigrid<3, double> linear(problem);
  linear.solve(1e-10, 60);
  double difference = 0, size = 0;
  for (int i = 0; i < 3; ++i)
    for (std::size_t k = 0; k < linear.finest().size(); ++k) {
      if (linear.finest().kind(i, k) != VarKind::INTERIOR) continue;
      difference = std::max(difference, std::abs(corotated.solution_level().x[i][k] -
                                                 linear.solution_level().x[i][k]));
      size = std::max(size, std::abs(linear.solution_level().x[i][k]));
    }
  std::printf("tip deflection %.3g, max difference corotated - linear %.3g\n", size, difference);
  EXPECT_LT(difference, 1e-4 * size);
}

ElasticityProblem<3> bent_cantilever() {
  ElasticityProblem<3> problem = end_clamped_bar(24, 0.475, true);
  problem.body_force = [](const Vec<3>&) { return Vec<3>(0, -0.01, 0); };
  return problem;
}

// The paper's Fig. 10 measures ~0.43 per cycle (non-linear residual, nu = 0.475, animation).
// Here from a cold start (u = 0) to a cantilever bent by a fifth of its length. Refreshing every
// cycle with Anderson mixing (default) meets 0.5; plain frozen-rotation cycles (depth 0) and
// k = 5 are limited by the outer iteration (next test) and only reported. Newton-Krylov steps of
// k = 5 directions: 0.834 (Picard with Anderson, k = 5: 0.884); with k = 1 from this cold start
// it stagnates (the first V-cycle's direction at R = I raises the frozen residual 5x, so its
// best step length is ~0), hence not the quasistatic default.
TEST(CorotatedMultigrid, NonlinearResidualOfABentNearlyIncompressibleBarDropsPerCycle) {
  const ElasticityProblem<3> problem = bent_cantilever();
  struct Variant {
    int every, depth;
    double bound;
    CorotatedOuter outer = CorotatedOuter::PICARD;
  };
  for (const Variant variant : {Variant{1, 3, 0.5}, Variant{1, 0, 0.65}, Variant{5, 3, 0.92},
                                Variant{5, 0, 0.86, CorotatedOuter::NEWTON_KRYLOV}}) {
    CorotatedOptions options;
    options.rotation_update_every = variant.every;
    options.acceleration_depth = variant.depth;
    options.outer = variant.outer;
    CorotatedMultigrid<3> corotated(problem, {}, options);
    const CorotatedReport report = corotated.solve(0.0, 30);
    double tip = 0;
    const auto& level = corotated.solution_level();
    for (std::size_t k = 0; k < level.size(); ++k)
      if (level.kind(1, k) == VarKind::INTERIOR) tip = std::min(tip, level.x[1][k]);
    const double rate = mean_rate(report.nonlinear);
    const double quasi_linear_rate = mean_rate(report.quasi_linear);
    std::printf(
        "bent bar nu 0.475, 24x6x6, rotations every %d cycles, %s, Anderson depth %d: tip "
        "deflection %.3f, non-linear residual %.3g -> %.3g in %d cycles, mean rate %.3f "
        "(quasi-linear %.3f), %.2f s\n",
        variant.every, variant.outer == CorotatedOuter::PICARD ? "Picard" : "Newton-Krylov",
        variant.depth, tip, report.nonlinear.front(), report.nonlinear.back(), report.cycles(),
        rate, quasi_linear_rate, report.seconds);
    EXPECT_LT(tip, -0.15);
    EXPECT_LE(rate, variant.bound) << "every " << variant.every << ", depth " << variant.depth;
  }
}

// Diagnosis of the outer iteration: with the frozen system solved (almost) exactly between
// refreshes, the non-linear residual still drops only ~0.46 per refresh (the Picard contraction
// of the co-rotated iteration on this bar), while a V-cycle on the frozen system reduces its own
// residual by ~0.37. One plain cycle per refresh cannot beat the former.
TEST(CorotatedMultigrid, FrozenRotationIterationContractsAboutHalfPerRefreshWithExactInnerSolves) {
  CorotatedOptions options;
  options.rotation_update_every = 1 << 30;  // refreshed by hand below
  options.acceleration_depth = 0;
  CorotatedMultigrid<3> corotated(bent_cantilever(), {}, options);
  std::vector<double> nonlinear{corotated.nonlinear_residual()};
  double inner_rate = 0;
  for (int outer = 0; outer < 7; ++outer) {
    corotated.refresh_rotations();
    const double start = corotated.quasi_linear_residual();
    double residual = start;
    int cycles = 0;
    while (residual > 1e-7 * start && cycles < 30) {
      residual = corotated.vcycle();
      ++cycles;
    }
    inner_rate = std::pow(residual / start, 1.0 / cycles);
    nonlinear.push_back(corotated.nonlinear_residual());
  }
  // The first refreshes leave the linear (R = I) overshoot; the late ratios are the contraction.
  const double contraction = std::pow(nonlinear[7] / nonlinear[4], 1.0 / 3);
  std::printf("frozen-rotation (Picard) contraction per refresh %.3f, inner V-cycle rate %.3f\n",
              contraction, inner_rate);
  EXPECT_GT(contraction, 0.3);
  EXPECT_LT(contraction, 0.55);
  EXPECT_LT(inner_rate, 0.45);
}

// The non-linear residual between refreshes is evaluated stress by stress without stored rows;
// it must be the residual of the stored rows (same rotations, same x).
TEST(CorotatedOperator, MatrixFreeResidualEqualsTheStoredRows) {
  const ElasticityProblem<3> problem = end_clamped_bar(16, 0.45, true);
  const BoundaryStress<3> traction = [](int i, int j, const Vec<3>& x) {
    return 0.01 * (i + 1) * (j + 2) * x[0];
  };
  Level<3, double> level = build_level<3, double>(problem.lattice, problem.cells, problem.material,
                                                  traction, nullptr, 5.0);
  std::uint32_t seed = 7;
  for (auto& field : level.x)
    for (double& v : field) {
      seed = seed * 1664525u + 1013904223u;
      v = 0.05 * (static_cast<double>(seed >> 8) / (1u << 24) - 0.5);
    }
  const auto rotations = cell_rotations(level);
  for (auto& field : level.b) std::fill(field.begin(), field.end(), 0.1);
  const double stored =
      corotated_residual(level, build_corotated_rows(level, rotations, traction, false));
  const auto stored_r = level.r;
  const double matrix_free = corotated_residual(level, rotations, traction, false);
  double worst = 0;
  for (int f = 0; f < 4; ++f)
    for (std::size_t k = 0; k < level.size(); ++k)
      worst = std::max(worst, std::abs(level.r[f][k] - stored_r[f][k]));
  std::printf("residual norm stored %.6g, matrix-free %.6g, max difference %.3g\n", stored,
              matrix_free, worst);
  EXPECT_GT(stored, 0.0);
  EXPECT_LT(worst, 1e-12 * stored);
}

TEST(CorotatedOperator, RowsAndResidualDoNotDependOnTheThreadCount) {
  const ElasticityProblem<3> problem = end_clamped_bar(16, 0.45, true);
  Level<3, double> level =
      build_level<3, double>(problem.lattice, problem.cells, problem.material, {}, nullptr);
  for (std::size_t k = 0; k < level.size(); ++k)
    level.x[1][k] = 0.2 * std::sin(0.37 * static_cast<double>(k));
  const auto rotations = cell_rotations(level);
  const int saved = thread_count();
  set_thread_count(1);
  const CorotatedRows one = build_corotated_rows(level, rotations, {}, false);
  const double residual_one = corotated_residual(level, rotations, {}, false);
  set_thread_count(2);
  const CorotatedRows two = build_corotated_rows(level, rotations, {}, false);
  const double residual_two = corotated_residual(level, rotations, {}, false);
  set_thread_count(saved);
  EXPECT_EQ(one.start, two.start);
  EXPECT_EQ(one.column, two.column);
  EXPECT_EQ(one.value, two.value);
  EXPECT_EQ(one.constant, two.constant);
  EXPECT_EQ(residual_one, residual_two);
}

// A refresh rebuilds rows, and a non-linear residual its stresses, in storage kept from the
// previous call: the results must be those of fresh storage (no entry of the earlier rotations
// or displacement left behind).
TEST(CorotatedOperator, RowsAndResidualInReusedStorageEqualFreshOnes) {
  const ElasticityProblem<3> problem = end_clamped_bar(16, 0.45, true);
  Level<3, double> level =
      build_level<3, double>(problem.lattice, problem.cells, problem.material, {}, nullptr);
  const auto bend = [&](double amplitude) {
    for (std::size_t k = 0; k < level.size(); ++k)
      level.x[1][k] = amplitude * std::sin(0.37 * static_cast<double>(k));
  };
  bend(0.3);
  CorotatedRows reused;
  build_corotated_rows(level, cell_rotations(level), {}, false, CorotatedStress::SYMMETRIZED,
                       reused);
  CorotatedResidualScratch<3> scratch;
  std::vector<Matrix<3>> rotations;
  cell_rotations(level, rotations);
  corotated_residual(level, rotations, {}, false, CorotatedStress::SYMMETRIZED, &scratch);

  bend(0.05);
  cell_rotations(level, rotations);
  const std::vector<Matrix<3>> fresh_rotations = cell_rotations(level);
  for (std::size_t k = 0; k < level.size(); ++k) ASSERT_EQ(rotations[k], fresh_rotations[k]);
  build_corotated_rows(level, rotations, {}, false, CorotatedStress::SYMMETRIZED, reused);
  const CorotatedRows fresh = build_corotated_rows(level, rotations, {}, false);
  EXPECT_EQ(reused.target, fresh.target);
  EXPECT_EQ(reused.start, fresh.start);
  EXPECT_EQ(reused.column, fresh.column);
  EXPECT_EQ(reused.value, fresh.value);
  EXPECT_EQ(reused.constant, fresh.constant);
  EXPECT_EQ(reused.row_of, fresh.row_of);
  const double with_scratch =
      corotated_residual(level, rotations, {}, false, CorotatedStress::SYMMETRIZED, &scratch);
  const auto r_with_scratch = level.r;
  const double without = corotated_residual(level, rotations, {}, false);
  EXPECT_EQ(with_scratch, without);
  for (int f = 0; f < 4; ++f)
    for (std::size_t k = 0; k < level.size(); ++k) ASSERT_EQ(r_with_scratch[f][k], level.r[f][k]);
}

// The box sweeps run colored zones in parallel: a co-rotated solve gives the same residual
// history and displacement, bit for bit, for 1, 2 and 3 threads (a bar of 48 x 12 x 12 cells:
// zones of one color side by side on the finest level).
TEST(CorotatedMultigrid, SolveDoesNotDependOnTheThreadCount) {
  ElasticityProblem<3> problem = end_clamped_bar(48, 0.475, true);
  problem.body_force = [](const Vec<3>&) { return Vec<3>(0, -0.01, 0); };
  const auto solve = [&](int threads) {
    set_thread_count(threads);
    CorotatedOptions options;
    options.rotation_update_every = 2;
    CorotatedMultigrid<3> corotated(problem, {}, options);
    const CorotatedReport report = corotated.solve(0.0, 4);
    std::vector<double> values = report.nonlinear;
    const auto& level = corotated.solution_level();
    for (int f = 0; f <= 3; ++f) values.insert(values.end(), level.x[f].begin(), level.x[f].end());
    return values;
  };
  const int saved = thread_count();
  const auto one = solve(1), two = solve(2), three = solve(3);
  set_thread_count(saved);
  ASSERT_EQ(one.size(), two.size());
  for (std::size_t i = 0; i < one.size(); ++i) {
    ASSERT_EQ(one[i], two[i]) << "entry " << i;
    ASSERT_EQ(one[i], three[i]) << "entry " << i;
  }
}

TEST(CorotatedMultigrid, InvertedCellsNeverGiveNaN) {
  ElasticityProblem<3> problem = end_clamped_bar(16, 0.45, false);
  // Both ends pushed through each other: F_xx = -0.5 along the bar (every cell inverted).
  problem.dirichlet_displacement = [](const Vec<3>& x) -> Vec<3> {
    return Vec<3>(-1.5 * (x[0] - 0.5), 0, 0);
  };
  CorotatedMultigrid<3> corotated(problem);
  const CorotatedReport report = corotated.run_cycles(15);
  for (double r : report.nonlinear) EXPECT_TRUE(std::isfinite(r));
  for (double r : report.quasi_linear) EXPECT_TRUE(std::isfinite(r));
  EXPECT_TRUE(all_finite(corotated.solution_level()));
  // A collapsed (singular) deformation: all Dirichlet faces at one point.
  problem.dirichlet_displacement = [](const Vec<3>& x) -> Vec<3> { return -x; };
  CorotatedMultigrid<3> collapsed(problem);
  collapsed.run_cycles(5);
  EXPECT_TRUE(all_finite(collapsed.solution_level()));
}

TEST(CorotatedBackwardEuler, FreeFallIsExactWithAndWithoutDamping) {
  // No constraint, gravity only: a uniform translation is strain free in both models, so every
  // face follows backward Euler's free fall u_n = g dt^2 n (n + 1) / 2 (damping acts on strain
  // rates only).
  for (double damping : {0.0, 0.01}) {
    ElasticityProblem<3> problem =
        test::unit_box<3>(8, Material{1e5, 0.3}, [](const IVec<3>&) { return false; });
    const double g = -9.81, density = 1000;
    problem.body_force = [&](const Vec<3>&) { return Vec<3>(0, density * g, 0); };
    const TimeStepOptions options{.dt = 1.0 / 30,
                                  .density = density,
                                  .damping = damping,
                                  .vcycles_per_step = 0,
                                  .tolerance = 1e-10};
    CorotatedBackwardEuler<3> sim(problem, options);
    const int steps = 5;
    for (int n = 0; n < steps; ++n) sim.step();
    const double expected = g * options.dt * options.dt * steps * (steps + 1) / 2;
    const Field fall = [&](const Vec<3>&) -> Vec<3> { return Vec<3>(0, expected, 0); };
    EXPECT_LT(max_face_error(sim.multigrid().solution_level(), fall), 1e-8 * std::abs(expected))
        << "damping " << damping;
    EXPECT_NEAR(sim.time(), steps * options.dt, 1e-12);
  }
}

}  // namespace
}  // namespace mgelastic::grid
