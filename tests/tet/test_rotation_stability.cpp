// Stability: a bar stretched to 2.5x and twisted by a full turn (a small version of the paper's
// horse experiment, Fig. 4/5), then held. Element flutter is measured as the step-to-step change
// of element rotations during the hold phase, for each rotation method.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "mgelastic/tet/corotated_solver.hpp"
#include "tet/tet_test_support.hpp"

namespace mgelastic::tet {
namespace {

constexpr double kLength = 1.0, kWidth = 0.25;
constexpr int kRampSteps = 50, kHoldSteps = 50, kMeasuredSteps = 25;

struct Flutter {
  double mean = 0.0;  // mean over elements and hold steps of the rotation change, radians
  double max = 0.0;   // largest single-element change in the hold phase
};

Flutter run_twisted_bar(RotationMethod method) {
  const geometry::TetMesh mesh =
      test::box_mesh(Eigen::Vector3d(kLength, kWidth, kWidth), kWidth / 3.0);
  CorotatedSolverSettings settings;
  settings.rotation_method = method;
  settings.time_step = 1.0 / 60.0;
  settings.pcg.tolerance = 1e-8;
  // Damped, so the held bar comes to rest: what keeps turning in the late hold phase is flutter,
  // not the bar's motion.
  settings.rayleigh_alpha = 5.0;
  CorotatedSolver solver(mesh, ElementMaterials::uniform(mesh.tet_count(), {1e5, 0.3, 1000.0}),
                         settings);
  std::vector<int> ends;
  for (int v = 0; v < mesh.vertex_count(); ++v)
    if (mesh.vertices(v, 0) < 1e-9 || mesh.vertices(v, 0) > kLength - 1e-9) ends.push_back(v);
  const double ramp_time = kRampSteps * settings.time_step;
  solver.set_dirichlet(ends, [&](int, const Eigen::Vector3d& x, double t) {
    if (x.x() < 0.5 * kLength) return x;
    const double s = std::min(t / ramp_time, 1.0);
    const Eigen::Vector3d axis_point(0, 0.5 * kWidth, 0.5 * kWidth);
    const Eigen::AngleAxisd twist(2.0 * std::numbers::pi * s, Eigen::Vector3d::UnitX());
    Eigen::Vector3d p = axis_point + twist * (x - axis_point);
    p.x() = x.x() * (1.0 + 1.5 * s);
    return p;
  });
  Flutter flutter;
  std::vector<Eigen::Quaterniond> previous;
  for (int step = 0; step < kRampSteps + kHoldSteps; ++step) {
    solver.step();
    if (step >= kRampSteps + kHoldSteps - kMeasuredSteps) {
      const auto& q = solver.rotations().quaternions();
      for (std::size_t e = 0; e < q.size(); ++e) {
        const double angle = q[e].angularDistance(previous[e]);
        flutter.mean += angle;
        flutter.max = std::max(flutter.max, angle);
      }
    }
    previous = solver.rotations().quaternions();
  }
  EXPECT_TRUE(solver.positions().allFinite());
  flutter.mean /= static_cast<double>(kMeasuredSteps * mesh.tet_count());
  return flutter;
}

TEST(RotationStability, StretchedTwistedBarStaysCalmWithEnergyMinimization) {
  const Flutter energy = run_twisted_bar(RotationMethod::ENERGY_MINIMIZATION);
  const Flutter polar = run_twisted_bar(RotationMethod::POLAR);
  const Flutter smoothed = run_twisted_bar(RotationMethod::POLAR_SMOOTHED);
  std::printf(
      "[flutter] hold-phase rotation change per step (rad): energy-min mean %.3e max %.3e | "
      "polar mean %.3e max %.3e | polar+smoothing mean %.3e max %.3e\n",
      energy.mean, energy.max, polar.mean, polar.max, smoothed.mean, smoothed.max);
  EXPECT_TRUE(std::isfinite(energy.mean) && std::isfinite(polar.mean) &&
              std::isfinite(smoothed.mean));
  // The damped, held bar settles: energy minimization does not make single elements jump (well
  // under a degree per step; flutter shows up as O(0.1) rad jumps), and its largest jump is not
  // worse than polar decomposition's (margin 1.5x plus a floor for when both are at rest). The
  // means are dominated by the bar's residual slow motion, so they are reported, not compared.
  EXPECT_LT(energy.max, 0.01);
  EXPECT_LE(energy.max, 1.5 * polar.max + 1e-6);
}

// Throughput on a ~12k-tet bar (reported, not asserted): steps/s with energy-minimization
// rotations, implicit Euler and block-Jacobi PCG, and the time per phase.
TEST(RotationStability, ReportsStepsPerSecondOn12kTetBar) {
  const geometry::TetMesh mesh = test::box_mesh(Eigen::Vector3d(2.0, 0.5, 0.5), 1.0 / 16.0);
  CorotatedSolverSettings settings;
  settings.gravity = Eigen::Vector3d(0, -9.81, 0);
  settings.pcg.tolerance = 1e-6;
  CorotatedSolver solver(mesh, ElementMaterials::uniform(mesh.tet_count(), {1e5, 0.3, 1000.0}),
                         settings);
  std::vector<int> clamped;
  for (int v = 0; v < mesh.vertex_count(); ++v)
    if (mesh.vertices(v, 0) < 1e-9) clamped.push_back(v);
  solver.set_dirichlet(clamped);
  StepStats sum;
  int iterations = 0;
  const int steps = 10;
  for (int i = 0; i < steps; ++i) {
    const StepStats& s = solver.step();
    sum.rotate_seconds += s.rotate_seconds;
    sum.assemble_seconds += s.assemble_seconds;
    sum.solve_seconds += s.solve_seconds;
    sum.total_seconds += s.total_seconds;
    iterations += s.solve.iterations;
  }
  std::printf(
      "[throughput] %d tets: %.1f steps/s; per step rotate %.2f ms, assemble %.2f ms, "
      "solve %.2f ms (%.0f PCG iterations)\n",
      mesh.tet_count(), steps / sum.total_seconds, 1e3 * sum.rotate_seconds / steps,
      1e3 * sum.assemble_seconds / steps, 1e3 * sum.solve_seconds / steps,
      static_cast<double>(iterations) / steps);
  EXPECT_TRUE(solver.positions().allFinite());
}

}  // namespace
}  // namespace mgelastic::tet
