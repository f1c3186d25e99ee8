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

const Material kSoft{1e5, 0.3};
constexpr double kDensity = 1000.0;

struct Swing {
  std::vector<double> energy, tip;
};

// A 16 x 4 x 4 cantilever (length 0.14 m free) swung by a 1 m/s tip velocity: the tip travels
// about 0.05 m, a third of the free length.
Swing swing(double damping, int steps, double dt) {
  const ElasticityProblem<3> problem = bar(16, 4, 0.01, 2, kSoft);
  CorotatedBackwardEuler<3> sim(problem, {.dt = dt, .density = kDensity, .damping = damping}, {},
                                {.rotation_update_every = 1});
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
  problem.body_force = [](const Vec<3>&) { return Vec<3>(0, -9.81 * kDensity, 0); };
  CorotatedBackwardEuler<3> sim(problem,
                                {.dt = dt, .density = kDensity, .vcycles_per_step = cycles}, {},
                                {.rotation_update_every = every, .smoother = smoother, .step_outer = outer,
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

// One cycle per step is one frozen-rotation (Picard) iteration. Measured over 30 steps: mean
// 0.374 (k = 1) and 0.416 (k = 5; the rotations of a step may be up to 4 steps old). Even an
// exact solve of the frozen system gives only 0.27 per step (one refresh), so one cycle cannot
// reach the 0.15 (linear model: 0.10); two cycles (two refreshes) can, see below.
TEST_F(CorotatedDynamics, OneVCyclePerStepReducesTheResidualAt30Fps) {
  for (const int every : {1, 5}) {
    const auto [mean, worst] = step_rates(0.45, 1.0 / 30, 30, every, 1);
    std::printf(
        "co-rotated per-step reduction, nu = 0.45, dt = 1/30, k = %d, 1 cycle: mean %.3f, "
        "worst %.3f\n",
        every, mean, worst);
    EXPECT_LE(mean, every == 1 ? 0.42 : 0.46);
    EXPECT_LT(worst, every == 1 ? 0.9 : 1.4);
  }
}

// The distributive smoother moves the one-cycle step rate only a little (measured mean 0.349,
// worst 0.774; box 0.377 / 0.776): the single refresh per step is the limit (see above).
TEST_F(CorotatedDynamics, DistributiveSmootherGivesTheSameOneCycleStepRate) {
  const auto [mean, worst] =
      step_rates(0.45, 1.0 / 30, 30, 1, 1, nullptr, CorotatedSmoother::DISTRIBUTIVE);
  std::printf(
      "co-rotated per-step reduction, nu = 0.45, dt = 1/30, k = 1, 1 cycle, distributive "
      "smoother: mean %.3f, worst %.3f\n",
      mean, worst);
  EXPECT_LE(mean, 0.40);
  EXPECT_LT(worst, 0.9);
}

// The target (<= 0.15 per step at a 30 fps frame) with two cycles per step, k = 1
// (measured mean 0.121, worst 0.529 over 30 steps).
TEST_F(CorotatedDynamics, TwoVCyclesPerStepMeetTheRateTargetAt30Fps) {
  const auto [mean, worst] = step_rates(0.45, 1.0 / 30, 30, 1, 2);
  std::printf(
      "co-rotated per-step reduction, nu = 0.45, dt = 1/30, k = 1, 2 cycles: mean %.3f, worst "
      "%.3f\n",
      mean, worst);
  EXPECT_LE(mean, 0.15);
  EXPECT_LT(worst, 0.7);
}

// nu = 0.49, dt = 1/24 s, a bar sagging and swinging by about half its length: 48 steps (2 s)
// stay finite and every step's cycles reduce the residual. Measured: 2 cycles per step mean
// 0.145, worst 0.543. (Before the traction variables were back-substituted after the
// prediction, this run diverged after 16 steps.)
TEST_F(CorotatedDynamics, LargeStepAtNearIncompressibilityConverges) {
  bool finite = false;
  const auto [mean, worst] = step_rates(0.49, 1.0 / 24, 48, 1, 2, &finite);
  std::printf("co-rotated nu = 0.49, dt = 1/24, 48 steps, 2 cycles: mean %.3f, worst %.3f\n", mean,
              worst);
  EXPECT_TRUE(finite);
  EXPECT_LE(mean, 0.2);
  EXPECT_LT(worst, 0.8);
}

TEST_F(CorotatedDynamics, NewtonKrylovProbe) {
  struct V { int cycles, every; CorotatedOuter outer; };
  for (const V v : {V{1, 1, CorotatedOuter::PICARD}, V{1, 1, CorotatedOuter::NEWTON_KRYLOV},
                    V{1, 5, CorotatedOuter::PICARD}, V{1, 5, CorotatedOuter::NEWTON_KRYLOV},
                    V{2, 2, CorotatedOuter::NEWTON_KRYLOV}}) {
    double seconds = 0;
    const auto [mean, worst] = step_rates(0.45, 1.0 / 30, 30, v.every, v.cycles, nullptr,
                                          CorotatedSmoother::BOX, v.outer, &seconds);
    std::printf("probe %s cycles %d k %d: mean %.3f worst %.3f %.3f s/step\n",
                v.outer == CorotatedOuter::PICARD ? "picard" : "newton", v.cycles, v.every, mean,
                worst, seconds);
    std::fflush(stdout);
  }
}

TEST_F(CorotatedDynamics, DivergedStepThrowsNamingTheTime) {
  const ElasticityProblem<3> problem = bar(16, 4, 0.01, 2, kSoft);
  CorotatedBackwardEuler<3> sim(problem, {.dt = 0.01, .density = kDensity});
  sim.step();
  const auto& level = sim.multigrid().solution_level();
  const std::ptrdiff_t k = level.lattice.index(IVec<3>(10, 2, 2));
  ASSERT_EQ(level.kind[1][k], VarKind::INTERIOR);
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
