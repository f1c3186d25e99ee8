// Backward-Euler dynamics of the grid engine (Sec. 8): exact free fall and rigid driving,
// bounded energy of an oscillating bar, damped envelope, V-cycle rate per step at a 30 fps
// step, and a large step at nu = 0.49.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "dynamics_test_support.hpp"
#include "mgelastic/core/error.hpp"
#include "mgelastic/core/threads.hpp"
#include "mgelastic/grid/backward_euler.hpp"
#include "mgelastic/grid/box_problem.hpp"
#include "mgelastic/grid/convergence_rate.hpp"
#include "mgelastic/grid/nonaugmented_system.hpp"

namespace mgelastic::grid {
namespace {

using test::bar;
using test::bending_velocity;

// Elastic energy 1/2 u^T A u h^3 of the discrete static system (zero Dirichlet values).
class ElasticEnergy {
 public:
  explicit ElasticEnergy(const ElasticityProblem<3>& problem)
      : m_level(
            build_level<3, double>(problem.lattice, problem.cells, problem.material, {}, nullptr)),
        m_system(assemble_nonaugmented(m_level, BoundaryStress<3>{})) {}
  double operator()(const Level<3, double>& solution) const {
    Eigen::VectorXd u(m_system.u_variables.size());
    for (std::size_t i = 0; i < m_system.u_variables.size(); ++i)
      u[i] = solution.at(m_system.u_variables[i]);
    return 0.5 * u.dot(m_system.matrix * u) * std::pow(m_level.lattice.h, 3);
  }

 private:
  Level<3, double> m_level;
  NonAugmentedSystem<3> m_system;
};

// The lattices here are small and some tests take 1000 steps: one thread avoids the OpenMP
// overhead, which dominates on small lattices and on a loaded machine (results do not depend on
// the thread count, Threads.ResultsDoNotDependOnThreadCount).
class BackwardEulerDynamics : public ::testing::Test {
 protected:
  void SetUp() override { set_thread_count(1); }
  void TearDown() override { set_thread_count(m_saved); }

 private:
  int m_saved = thread_count();
};

const Material kSoft{1e5, 0.3};
constexpr double kDensity = 1000.0;

TEST_F(BackwardEulerDynamics, FreeFallIsExact) {
  // No constraint: inertia alone makes the system definite; a uniform translation is strain
  // free, so every face must follow backward Euler's free fall u_n = g dt^2 n (n + 1) / 2.
  ElasticityProblem<3> problem = bar(16, 8, 0.01, 0, kSoft);
  const double g = -9.81;
  problem.body_force = [&](const Vec<3>&) { return Vec<3>(0, kDensity * g, 0); };
  TimeStepOptions options{
      .dt = 1.0 / 30, .density = kDensity, .vcycles_per_step = 0, .tolerance = 1e-10};
  BackwardEuler<3, double> sim(problem, options);
  const int steps = 10;
  for (int n = 0; n < steps; ++n) sim.step();
  const double expected = g * options.dt * options.dt * steps * (steps + 1) / 2;
  const auto& level = sim.multigrid().solution_level();
  double worst = 0;
  for (int i = 0; i < 3; ++i)
    for (std::size_t k = 0; k < level.size(); ++k)
      if (level.kind(i, k) != VarKind::INACTIVE)
        worst = std::max(worst, std::abs(level.x[i][k] - (i == 1 ? expected : 0.0)));
  EXPECT_LT(worst, 1e-8 * std::abs(expected));
}

TEST_F(BackwardEulerDynamics, RigidDrivingWithMatchingInitialVelocityStaysRigid) {
  // Dirichlet end translated at speed V and the body starting at V: the motion is a rigid
  // translation, which the warm start u + dt v predicts exactly, so one cycle per step keeps it.
  const ElasticityProblem<3> problem = bar(16, 8, 0.01, 2, kSoft);
  const Vec<3> speed(0.1, -0.2, 0.05);
  BackwardEuler<3, float> sim(problem, {.dt = 1.0 / 30, .density = kDensity});
  sim.set_velocity([&](const Vec<3>&) { return speed; });
  for (int n = 0; n < 20; ++n) {
    const double t = sim.time() + sim.options().dt;
    sim.step([&](const Vec<3>&) { return Vec<3>(speed * t); });
  }
  const auto& level = sim.multigrid().solution_level();
  double worst = 0;
  for (int i = 0; i < 3; ++i)
    for (std::size_t k = 0; k < level.size(); ++k)
      if (level.kind(i, k) != VarKind::INACTIVE)
        worst = std::max(worst, std::abs(level.x[i][k] - speed[i] * sim.time()));
  EXPECT_LT(worst, 1e-6 * speed.norm() * sim.time());
}

struct EnergyHistory {
  std::vector<double> total, tip;
};

EnergyHistory oscillate(double damping, int steps, double dt, int vcycles_per_step = 1) {
  const ElasticityProblem<3> problem = bar(24, 6, 0.01, 2, kSoft);
  const ElasticEnergy elastic(problem);
  BackwardEuler<3, double> sim(problem, {.dt = dt,
                                         .density = kDensity,
                                         .damping = damping,
                                         .vcycles_per_step = vcycles_per_step,
                                         .tolerance = 1e-10,
                                         .max_vcycles = 100});
  sim.set_velocity(bending_velocity(0.02, 0.22, 0.1));
  const auto& level = sim.multigrid().solution_level();
  const std::ptrdiff_t tip = level.lattice.index(IVec<3>(24, 4, 3));  // u_y face at the free end
  EnergyHistory history;
  history.total.push_back(sim.kinetic_energy() + elastic(level));
  history.tip.push_back(0.0);
  for (int n = 0; n < steps; ++n) {
    sim.step();
    history.total.push_back(sim.kinetic_energy() + elastic(level));
    history.tip.push_back(level.x[1][tip]);
  }
  return history;
}

TEST_F(BackwardEulerDynamics, UndampedBarKeepsBoundedEnergyOver1000Steps) {
  // Backward Euler only dissipates; one V-cycle per step must not add energy. For the first
  // bending mode (omega ~ 10.6 rad/s) at dt = 2 ms the exact scheme keeps (1 + (omega dt)^2)^-1000
  // ~ 0.64 of the energy; higher modes in the initial profile are damped faster.
  const EnergyHistory h = oscillate(0.0, 1000, 2e-3);
  const double e0 = h.total.front();
  double worst_growth = 0;
  for (std::size_t n = 1; n < h.total.size(); ++n)
    worst_growth = std::max(worst_growth, h.total[n] / h.total[n - 1] - 1.0);
  std::printf("undamped bar: E_1000 / E_0 = %.4f, worst step growth %.2e\n", h.total.back() / e0,
              worst_growth);
  EXPECT_LT(*std::max_element(h.total.begin(), h.total.end()), e0 * (1 + 1e-6));
  EXPECT_LT(worst_growth, 1e-6);
  EXPECT_GT(h.total.back(), 0.4 * e0);  // still oscillating: no spurious dissipation
}

TEST_F(BackwardEulerDynamics, ConvergedDampedStepsNeverAddEnergy) {
  // Solved to 1e-10, each damped step dissipates (the energy identity of backward Euler with
  // Rayleigh damping): the right-hand side's damping and inertia terms are consistent.
  const EnergyHistory damped = oscillate(0.01, 100, 2e-3, 0);
  for (std::size_t n = 1; n < damped.total.size(); ++n)
    ASSERT_LE(damped.total[n], damped.total[n - 1] * (1 + 1e-9)) << "step " << n;
}

TEST_F(BackwardEulerDynamics, DampingMakesTheEnvelopeDecayMonotonically) {
  const EnergyHistory undamped = oscillate(0.0, 1000, 2e-3);
  const EnergyHistory damped = oscillate(0.01, 1000, 2e-3);
  // Peaks of |u_tip| (half periods).
  std::vector<double> peaks;
  for (std::size_t n = 1; n + 1 < damped.tip.size(); ++n) {
    const double a = std::abs(damped.tip[n]);
    if (a > std::abs(damped.tip[n - 1]) && a >= std::abs(damped.tip[n + 1])) peaks.push_back(a);
  }
  ASSERT_GE(peaks.size(), 5u);
  for (std::size_t p = 1; p < peaks.size(); ++p) EXPECT_LT(peaks[p], peaks[p - 1]) << "peak " << p;
  // Converged steps never add energy (previous test); one V-cycle per step leaves an error that
  // can (measured: worst 8.8e-4 of the current energy, late, when the energy is 1% of the
  // initial one).
  double worst_growth = 0;
  for (std::size_t n = 1; n < damped.total.size(); ++n)
    worst_growth = std::max(worst_growth, damped.total[n] / damped.total[n - 1] - 1.0);
  EXPECT_LT(worst_growth, 3e-3);
  EXPECT_LT(*std::max_element(damped.total.begin() + 1, damped.total.end()), damped.total.front());
  std::printf(
      "damped bar: E_1000 / E_0 = %.4f (undamped %.4f), %zu peaks, last/first %.3f, worst step "
      "growth %.2e\n",
      damped.total.back() / damped.total.front(), undamped.total.back() / undamped.total.front(),
      peaks.size(), peaks.back() / peaks.front(), worst_growth);
  EXPECT_LT(damped.total.back(), 0.5 * undamped.total.back());
}

// Residual reduction of the single V-cycle of each step, bar sagging and swinging under gravity
// from an initial velocity: {geometric mean, worst} over the steps.
std::pair<double, double> step_rates(double poisson, double dt, int steps, bool* finite = nullptr) {
  ElasticityProblem<3> problem = bar(32, 8, 0.01, 2, {1e5, poisson});
  problem.body_force = [](const Vec<3>&) { return Vec<3>(0, -9.81 * kDensity, 0); };
  BackwardEuler<3, float> sim(problem, {.dt = dt, .density = kDensity});
  sim.set_velocity(bending_velocity(0.02, 0.3, 0.5));
  test::StepRates rates;
  for (int n = 0; n < steps; ++n) {
    const SolveReport report = sim.step();
    rates.add(report.residuals.back() / report.residuals.front());
  }
  if (finite) *finite = test::all_finite(sim.velocity());
  return rates.mean_and_worst();
}

TEST_F(BackwardEulerDynamics, OneVCyclePerStepReducesTheResidualAt30Fps) {
  // Paper: 0.08 per V-cycle for its car. Measured here over 60 steps: mean 0.10, most steps
  // 0.08-0.10; the worst, 0.23, at the bar's turning points, where the new step's residual is
  // small next to the error carried over from earlier single-cycle steps.
  const auto [mean, worst] = step_rates(0.45, 1.0 / 30, 60);
  std::printf("per-step V-cycle reduction, nu = 0.45, dt = 1/30: mean %.3f, worst %.3f\n", mean,
              worst);
  EXPECT_LE(mean, 0.15);
  EXPECT_LE(worst, 0.3);
}

TEST_F(BackwardEulerDynamics, LargeStepAtNearIncompressibilityStaysFinite) {
  bool finite = false;
  const auto [mean, worst] = step_rates(0.49, 1.0 / 24, 48, &finite);
  std::printf("per-step V-cycle reduction, nu = 0.49, dt = 1/24: mean %.3f, worst %.3f\n", mean,
              worst);
  EXPECT_TRUE(finite);
  EXPECT_LE(mean, 0.15);
  EXPECT_LT(worst, 0.5);
}

// Sec. 8: the c-term in the rows and in the distribution (-2 Lap + c/mu). In the range of real
// runs (c h^2 / mu between 1e-3 and 1e-1: E ~ 1e5 Pa, h ~ 1 cm, dt ~ 1/30 s) the cycle converges
// as in statics; inertia-dominated systems (c >> mu / h^2) converge almost at once. Measured: a
// middle range (c h^2 / mu ~ 1 - 10) where the rate at nu = 0.49 is up to 0.33 instead of 0.20
// on the mixed box, and small c changes the static rate by up to 16% (0.191 -> 0.221, mixed box,
// nu = 0.3); the paper expects no slow-down (docs/grid-engine.md).
TEST_F(BackwardEulerDynamics, InertiaTermKeepsTheCyclesConverging) {
  const std::vector<double> ratios{0.0, 0.01, 0.1, 1.0, 10.0, 1000.0};
  for (const BoxBoundary boundary : {BoxBoundary::MIXED, BoxBoundary::DIRICHLET}) {
    for (const double nu : {0.3, 0.49}) {
      ElasticityProblem<3> problem =
          make_box_problem<3>({.cells = 16, .poisson_ratio = nu, .boundary = boundary});
      const double stiffness = problem.material.mu() / std::pow(problem.lattice.h, 2);
      std::vector<double> rates;
      for (const double ratio : ratios) {
        problem.inertia = ratio * stiffness;
        Multigrid<3, double> mg(problem);
        rates.push_back(convergence_rate(mg.run_cycles(10).residuals));
      }
      std::printf("box %s nu %.2f, rate at c h^2 / mu =",
                  boundary == BoxBoundary::MIXED ? "mixed" : "dirichlet", nu);
      for (std::size_t c = 0; c < rates.size(); ++c) std::printf(" %g: %.3f", ratios[c], rates[c]);
      std::printf("\n");
      for (std::size_t c = 1; c <= 2; ++c) EXPECT_LE(rates[c], 1.2 * rates[0]) << ratios[c];
      for (double rate : rates) EXPECT_LT(rate, 0.6);
      EXPECT_LT(rates.back(), 0.05);  // inertia-dominated: nearly a mass matrix
    }
  }
}

TEST_F(BackwardEulerDynamics, DivergedStepThrowsNamingTheTime) {
  const ElasticityProblem<3> problem = bar(16, 8, 0.01, 2, kSoft);
  BackwardEuler<3, float> sim(problem, {.dt = 0.01, .density = kDensity});
  sim.step();
  const auto& level = sim.multigrid().solution_level();
  const std::ptrdiff_t k = level.lattice.index(IVec<3>(10, 4, 4));
  ASSERT_EQ(level.kind(1, k), VarKind::INTERIOR);
  sim.velocity()[1][k] = std::nan("");  // what a blown-up step would leave
  try {
    sim.step();
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("time step from t = 0.01 s diverged"), std::string::npos)
        << e.what();
  }
}

TEST_F(BackwardEulerDynamics, RejectsBadOptions) {
  const ElasticityProblem<3> problem = bar(16, 8, 0.01, 2, kSoft);
  EXPECT_THROW((BackwardEuler<3, double>(problem, {.dt = 0.0})), Error);
  EXPECT_THROW((BackwardEuler<3, double>(problem, {.dt = 0.01, .density = -1})), Error);
  EXPECT_THROW((BackwardEuler<3, double>(problem, {.dt = 0.01, .damping = -1})), Error);
  EXPECT_THROW((BackwardEuler<3, double>(problem, {.dt = 0.01, .vcycles_per_step = -1})), Error);
}

TEST_F(BackwardEulerDynamics, StaticProblemWithoutSupportIsStillRejected) {
  const ElasticityProblem<3> problem = bar(16, 8, 0.01, 0, kSoft);
  EXPECT_THROW((Multigrid<3, double>(problem)), Error);
}

}  // namespace
}  // namespace mgelastic::grid
