// Backward-Euler dynamics (Sec. 8) with the co-rotational model (Sec. 7): the acceptance items
// of the linear dynamics (test_backward_euler.cpp) rechecked with material.model corotated, on
// swings large enough (tip excursions of about a third of the bar) for the rotations to matter.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "dynamics_test_support.hpp"
#include "mgelastic/core/error.hpp"
#include "mgelastic/core/threads.hpp"
#include "mgelastic/grid/corotated_dynamics.hpp"

namespace mgelastic::grid {
namespace {

using test::bar;
using test::bending_velocity;
using test::corotated_energy;

class CorotatedDynamics : public ::testing::Test {
 protected:
  void SetUp() override { set_thread_count(1); }
  void TearDown() override { set_thread_count(m_saved); }

 private:
  int m_saved = thread_count();
};

const Material kSwingMaterial{1e5, 0.3};
constexpr double kSwingDensity = 1000.0;

struct Swing {
  std::vector<double> energy, tip;
};

// A 16 x 4 x 4 cantilever (length 0.14 m free) swung by a 1 m/s tip velocity: the tip travels
// about 0.05 m, a third of the free length.
Swing swing(double damping, int steps, double dt) {
  const ElasticityProblem<3> problem = bar(16, 4, 0.01, 2, kSwingMaterial);
  CorotatedBackwardEuler<3> sim(problem, {.dt = dt, .density = kSwingDensity, .damping = damping},
                                {}, {.rotation_update_every = 1});
  sim.set_velocity(bending_velocity(0.02, 0.14, 1.0));
  const auto& level = sim.multigrid().solution_level();
  const std::ptrdiff_t tip = level.lattice.index(IVec<3>(16, 3, 2));  // u_y face at the free end
  Swing history;
  history.energy.push_back(sim.kinetic_energy() + corotated_energy(level, problem.material));
  history.tip.push_back(0.0);
  for (int n = 0; n < steps; ++n) {
    sim.step();
    history.energy.push_back(sim.kinetic_energy() + corotated_energy(level, problem.material));
    history.tip.push_back(level.x[1][tip]);
  }
  return history;
}

TEST_F(CorotatedDynamics, UndampedSwingKeepsBoundedEnergyOver1000Steps) {
  const Swing h = swing(0.0, 1000, 2e-3);
  const double e0 = h.energy.front();
  const double largest = *std::max_element(h.energy.begin(), h.energy.end());
  const double tip = *std::max_element(
      h.tip.begin(), h.tip.end(), [](double a, double b) { return std::abs(a) < std::abs(b); });
  std::printf(
      "undamped co-rotated swing: max |tip| %.4f m, E_max / E_0 = %.4f, E_1000 / E_0 = %.4f\n",
      std::abs(tip), largest / e0, h.energy.back() / e0);
  EXPECT_GT(std::abs(tip), 0.03);       // a large swing, not a small vibration
  EXPECT_LT(largest, e0 * (1 + 1e-3));  // no growth (cell energy, not the discrete form)
  // Backward Euler's own dissipation: the first mode (~24 rad/s) keeps (1 + (omega dt)^2)^-1000
  // ~ 0.1 of its energy.
  EXPECT_GT(h.energy.back(), 0.05 * e0);
}

TEST_F(CorotatedDynamics, DampingMakesTheEnvelopeDecayMonotonically) {
  const Swing damped = swing(0.01, 500, 2e-3);
  std::vector<double> peaks;
  for (std::size_t n = 1; n + 1 < damped.tip.size(); ++n) {
    const double a = std::abs(damped.tip[n]);
    if (a > std::abs(damped.tip[n - 1]) && a >= std::abs(damped.tip[n + 1])) peaks.push_back(a);
  }
  std::printf("damped co-rotated swing: %zu peaks, first %.4f m, last %.4f m\n", peaks.size(),
              peaks.empty() ? 0.0 : peaks.front(), peaks.empty() ? 0.0 : peaks.back());
  ASSERT_GE(peaks.size(), 3u);
  for (std::size_t p = 1; p < peaks.size(); ++p) EXPECT_LT(peaks[p], peaks[p - 1]) << "peak " << p;
}

// Non-linear residual reduction of each step's single V-cycle, a bar sagging and swinging under
// gravity from an initial velocity: {geometric mean, worst}.
std::pair<double, double> step_rates(double poisson, double dt, int steps, int every, int cycles,
                                     bool* finite = nullptr,
                                     CorotatedSmoother smoother = CorotatedSmoother::BOX,
                                     CorotatedOuter outer = CorotatedOuter::NEWTON_KRYLOV,
                                     double* seconds = nullptr, int recycled = 2) {
  ElasticityProblem<3> problem = bar(32, 8, 0.01, 2, {1e5, poisson});
  problem.body_force = [](const Vec<3>&) { return Vec<3>(0, -9.81 * kSwingDensity, 0); };
  CorotatedBackwardEuler<3> sim(
      problem, {.dt = dt, .density = kSwingDensity, .vcycles_per_step = cycles}, {},
      {.rotation_update_every = every,
       .smoother = smoother,
       .step_outer = outer,
       .recycled_directions = recycled});
  sim.set_velocity(bending_velocity(0.02, 0.3, 1.0));
  test::StepRates rates;
  double total = 0;
  for (int n = 0; n < steps; ++n) {
    const CorotatedReport report = sim.step();
    rates.add(report.nonlinear.back() / report.nonlinear.front());
    total += report.seconds;
  }
  if (finite) *finite = test::all_finite(sim.velocity());
  if (seconds) *seconds = total / steps;
  return rates.mean_and_worst();
}

// One cycle per step with the default Newton-Krylov step (CorotatedOptions::step_outer): the
// V-cycle direction and the corrections of the last two steps combined by minimal residual
// (corotated_newton_krylov.hpp). Measured over 30 steps: mean 0.116, worst 0.650 (k = 1);
// 0.247 / 0.799 (k = 5: the preconditioner's rotations up to 4 steps old). The issue asks
// <= 0.15 at a 30 fps frame (linear model: 0.10).
TEST_F(CorotatedDynamics, OneVCyclePerStepReducesTheResidualAt30Fps) {
  for (const int every : {1, 5}) {
    const auto [mean, worst] = step_rates(0.45, 1.0 / 30, 30, every, 1);
    std::printf(
        "co-rotated per-step reduction, nu = 0.45, dt = 1/30, k = %d, 1 cycle, Newton-Krylov: "
        "mean %.3f, worst %.3f\n",
        every, mean, worst);
    EXPECT_LE(mean, every == 1 ? 0.15 : 0.3);
    EXPECT_LT(worst, every == 1 ? 0.7 : 1.0);
  }
}

// The frozen-rotation (Picard) cycle misses the change of R(F): one cycle per step gives 0.377
// (even an exact frozen solve only 0.27). Same run: Newton-Krylov 0.116 at ~1.4x the solve
// time per step (loaded machine, separate runs: 0.22 against 0.16 s per step).
TEST_F(CorotatedDynamics, NewtonKrylovStepBeatsThePicardCycleAt30Fps) {
  double newton_seconds = 0, picard_seconds = 0;
  const auto newton = step_rates(0.45, 1.0 / 30, 30, 1, 1, nullptr, CorotatedSmoother::BOX,
                                 CorotatedOuter::NEWTON_KRYLOV, &newton_seconds);
  const auto picard = step_rates(0.45, 1.0 / 30, 30, 1, 1, nullptr, CorotatedSmoother::BOX,
                                 CorotatedOuter::PICARD, &picard_seconds);
  std::printf(
      "one cycle per step, k = 1: Newton-Krylov mean %.3f worst %.3f (%.3f s/step), Picard mean "
      "%.3f worst %.3f (%.3f s/step)\n",
      newton.first, newton.second, newton_seconds, picard.first, picard.second, picard_seconds);
  EXPECT_LT(newton.first, 0.5 * picard.first);
  EXPECT_LE(picard.first, 0.42);  // the Picard path still works as before
}

// Without recycled directions the Newton step is the Picard cycle with the best step length:
// measured 0.246 per step (below the exact frozen solve's 0.27), the last two corrections bring
// it to 0.116.
TEST_F(CorotatedDynamics, RecycledDirectionsImproveTheOneCycleStep) {
  const auto plain = step_rates(0.45, 1.0 / 30, 30, 1, 1, nullptr, CorotatedSmoother::BOX,
                                CorotatedOuter::NEWTON_KRYLOV, nullptr, 0);
  const auto recycled = step_rates(0.45, 1.0 / 30, 30, 1, 1);
  std::printf("Newton-Krylov one cycle per step: no recycled directions mean %.3f, two %.3f\n",
              plain.first, recycled.first);
  EXPECT_LE(plain.first, 0.3);
  EXPECT_LT(recycled.first, 0.7 * plain.first);
}

// The distributive smoother (Schur band) as the preconditioner (measured mean 0.100, worst
// 0.461; box smoother, same settings: 0.116 / 0.650).
TEST_F(CorotatedDynamics, DistributiveSmootherGivesTheSameOneCycleStepRate) {
  const auto [mean, worst] =
      step_rates(0.45, 1.0 / 30, 30, 1, 1, nullptr, CorotatedSmoother::DISTRIBUTIVE);
  std::printf(
      "co-rotated per-step reduction, nu = 0.45, dt = 1/30, k = 1, 1 cycle, distributive "
      "smoother: mean %.3f, worst %.3f\n",
      mean, worst);
  EXPECT_LE(mean, 0.15);
  EXPECT_LT(worst, 0.7);
}

// Two cycles per step (one Newton step with two V-cycle directions and two recycled ones):
// measured mean 0.072, worst 0.406 (Picard, two refreshes: 0.125 / 0.530).
TEST_F(CorotatedDynamics, TwoVCyclesPerStepMeetTheRateTargetAt30Fps) {
  const auto [mean, worst] = step_rates(0.45, 1.0 / 30, 30, 1, 2);
  std::printf(
      "co-rotated per-step reduction, nu = 0.45, dt = 1/30, k = 1, 2 cycles: mean %.3f, worst "
      "%.3f\n",
      mean, worst);
  EXPECT_LE(mean, 0.1);
  EXPECT_LT(worst, 0.6);
}

// nu = 0.49, dt = 1/24 s, a bar sagging and swinging by about half its length: 48 steps (2 s)
// stay finite and every step's cycles reduce the residual. Measured (Newton-Krylov): 2 cycles
// per step mean 0.091, worst 0.293; 1 cycle 0.175 / 0.722. (Before the traction variables were
// back-substituted after the prediction, this run diverged after 16 steps.)
TEST_F(CorotatedDynamics, LargeStepAtNearIncompressibilityConverges) {
  for (const int cycles : {1, 2}) {
    bool finite = false;
    const auto [mean, worst] = step_rates(0.49, 1.0 / 24, 48, 1, cycles, &finite);
    std::printf("co-rotated nu = 0.49, dt = 1/24, 48 steps, %d cycles: mean %.3f, worst %.3f\n",
                cycles, mean, worst);
    EXPECT_TRUE(finite);
    EXPECT_LE(mean, cycles == 1 ? 0.3 : 0.2);
    EXPECT_LT(worst, 0.9);
  }
}

// A keyframed limb (the skeleton_arm_corotated example in small): a 48 x 8 x 8 bar, clamped at
// x = 0, whose last cells are Dirichlet and turn about z around the bar's middle by 12 degrees
// per 1/30 s step from rest; one V-cycle per step. The first step starts with the end cells
// moved by up to 4.7 cells while their neighbours are still at rest (corotated_newton_krylov.hpp).
// Measured: first step 0.028, mean 0.164, worst 0.387; with tangent images and the non-linear
// residual's first direction (before 2026-12-07) 0.174, 0.317, 0.534 here, and 0.99-1.0 per step
// on the example arm at 160-256 cells.
TEST_F(CorotatedDynamics, KeyframedEndIsFollowedWithOneVCyclePerStep) {
  constexpr int nx = 48;
  constexpr double h = 0.6 / nx;
  ElasticityProblem<3> problem = bar(nx, 8, h, 2, {1e5, 0.45});
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(problem.lattice.size()); ++k)
    if (problem.lattice.is_real(problem.lattice.coords(k)) && problem.lattice.coords(k)[0] > nx - 4)
      problem.cells[k] = CellType::DIRICHLET;
  problem.body_force = [](const Vec<3>&) { return Vec<3>(0, -9.81 * kSwingDensity, 0); };
  CorotatedBackwardEuler<3> sim(problem,
                                {.dt = 1.0 / 30, .density = kSwingDensity, .damping = 0.005}, {},
                                {.rotation_update_every = 1});
  const Vec<3> pivot(0.3, 4 * h, 4 * h);
  std::vector<double> rates;
  for (int n = 1; n <= 6; ++n) {
    const Matrix<3> turn =
        Eigen::AngleAxisd(n * 12.0 * M_PI / 180, Eigen::Vector3d::UnitZ()).matrix();
    const CorotatedReport report = sim.step([&](const Vec<3>& x) -> Vec<3> {
      if (x[0] < pivot[0]) return Vec<3>::Zero();
      return (turn - Matrix<3>::Identity()) * (x - pivot);
    });
    rates.push_back(report.nonlinear.back() / report.nonlinear.front());
  }
  test::StepRates stats;
  for (const double r : rates) stats.add(r);
  const auto [mean, worst] = stats.mean_and_worst();
  std::printf(
      "keyframed end, 12 degrees per step, 1 cycle: first step %.3f, mean %.3f, worst %.3f\n",
      rates.front(), mean, worst);
  EXPECT_LE(rates.front(), 0.1);
  EXPECT_LE(mean, 0.25);
  EXPECT_LT(worst, 0.5);
}

TEST_F(CorotatedDynamics, DivergedStepThrowsNamingTheTime) {
  const ElasticityProblem<3> problem = bar(16, 4, 0.01, 2, kSwingMaterial);
  CorotatedBackwardEuler<3> sim(problem, {.dt = 0.01, .density = kSwingDensity});
  sim.step();
  const auto& level = sim.multigrid().solution_level();
  const std::ptrdiff_t k = level.lattice.index(IVec<3>(10, 2, 2));
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

}  // namespace
}  // namespace mgelastic::grid
