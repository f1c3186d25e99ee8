// Stability: a bar stretched to 2.5x and twisted by a full turn (a small version of the paper's
// horse experiment, Fig. 4/5), then held. Element flutter is measured as the step-to-step change
// of element rotations during the hold phase, for each rotation method.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>

#include "mgelastic/tet/corotated_solver.hpp"
#include "tet/tet_test_support.hpp"

namespace mgelastic::tet {
namespace {

constexpr double kLength = 1.0, kWidth = 0.25;

struct Flutter {
  double mean = 0.0;  // mean over elements and measured steps of the rotation change, radians
  double max = 0.0;   // largest single-element change in the measured steps
  int tets = 0;
};

struct TwistRun {
  int cells_across = 3;  // cubes across the width (6 tets each)
  int ramp_steps = 50;   // stretch and twist grow linearly over these steps, then hold
  int hold_steps = 50;
  int measured_steps = 25;  // the last steps of the hold phase
};

// Ends of the bar: x = 0 fixed, x = L stretched by 1.5 L and turned once about the bar's axis,
// both growing linearly until `ramp_time`.
DirichletMotion stretch_and_twist(double ramp_time) {
  return [ramp_time](int, const Eigen::Vector3d& x, double t) -> Eigen::Vector3d {
    if (x.x() < 0.5 * kLength) return x;
    const double s = std::min(t / ramp_time, 1.0);
    const Eigen::Vector3d axis_point(0, 0.5 * kWidth, 0.5 * kWidth);
    const Eigen::AngleAxisd twist(2.0 * std::numbers::pi * s, Eigen::Vector3d::UnitX());
    Eigen::Vector3d p = axis_point + twist * (x - axis_point);
    p.x() = x.x() * (1.0 + 1.5 * s);
    return p;
  };
}

std::vector<int> bar_ends(const geometry::TetMesh& mesh) {
  std::vector<int> ends;
  for (int v = 0; v < mesh.vertex_count(); ++v)
    if (mesh.vertices(v, 0) < 1e-9 || mesh.vertices(v, 0) > kLength - 1e-9) ends.push_back(v);
  return ends;
}

Flutter run_twisted_bar(RotationMethod method, const TwistRun& run = {}) {
  const geometry::TetMesh mesh =
      test::box_mesh(Eigen::Vector3d(kLength, kWidth, kWidth), kWidth / run.cells_across);
  CorotatedSolverSettings settings;
  settings.rotation_method = method;
  settings.time_step = 1.0 / 60.0;
  settings.pcg.tolerance = 1e-8;
  // Damped, so the held bar comes to rest: what keeps turning in the late hold phase is flutter,
  // not the bar's motion.
  settings.rayleigh_alpha = 5.0;
  CorotatedSolver solver(mesh, ElementMaterials::uniform(mesh.tet_count(), {1e5, 0.3, 1000.0}),
                         settings);
  solver.set_dirichlet(bar_ends(mesh), stretch_and_twist(run.ramp_steps * settings.time_step));
  Flutter flutter;
  flutter.tets = mesh.tet_count();
  std::vector<Eigen::Quaterniond> previous;
  const int steps = run.ramp_steps + run.hold_steps;
  for (int step = 0; step < steps; ++step) {
    solver.step();
    if (step >= steps - run.measured_steps) {
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
  flutter.mean /= static_cast<double>(run.measured_steps * mesh.tet_count());
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

// Issue 6: 500 steps (100 ramp, 400 hold) with each method side by side, flutter over the last
// 100 steps. 4 cells across (1 536 tets) by default, a few seconds; MGELASTIC_FLUTTER_FINE=1 runs
// 8 cells across (12 288 tets) as well.
TEST(RotationStability, FiveHundredStepTwistFlutterSideBySide) {
  std::vector<int> sizes = {4};
  const char* fine = std::getenv("MGELASTIC_FLUTTER_FINE");
  if (fine != nullptr && std::string(fine) == "1") sizes.push_back(8);
  for (int cells : sizes) {
    const TwistRun run{
        .cells_across = cells, .ramp_steps = 100, .hold_steps = 400, .measured_steps = 100};
    const Flutter energy = run_twisted_bar(RotationMethod::ENERGY_MINIMIZATION, run);
    const Flutter polar = run_twisted_bar(RotationMethod::POLAR, run);
    const Flutter smoothed = run_twisted_bar(RotationMethod::POLAR_SMOOTHED, run);
    std::printf(
        "[flutter 500 steps] %d tets, last 100 steps, rotation change per step (rad):\n"
        "  energy minimization  mean %.3e  max %.3e\n"
        "  polar                mean %.3e  max %.3e\n"
        "  polar + smoothing    mean %.3e  max %.3e\n",
        energy.tets, energy.mean, energy.max, polar.mean, polar.max, smoothed.mean, smoothed.max);
    EXPECT_TRUE(std::isfinite(polar.mean) && std::isfinite(smoothed.mean));
    // After 400 damped hold steps (alpha = 5/s: the motion has decayed by e^-16) a settled bar's
    // elements turn by round-off-level amounts per step; flutter is an element flipping back and
    // forth by a sizeable angle. 1e-4 rad (0.006 degrees) per step sits far above the settled level
    // and far below any flip.
    EXPECT_LT(energy.mean, 1e-5) << cells << " cells across";
    EXPECT_LT(energy.max, 1e-4) << cells << " cells across";
  }
}

// The quasistatic counterpart: equilibria of the bar at 10 stages of the stretch and twist. With
// rotations frozen per round the static iteration overshoots into a 2-cycle under large twist
// (stages 2-10 fail without it); the line search on the free residual force must make every
// stage converge to the 1e-6 relative update `mgelastic run` uses by default. Convergence is
// linear, ~0.97 per round at the full turn, so the round limit is generous.
TEST(RotationStability, QuasistaticTwistConvergesAtEveryStage) {
  const geometry::TetMesh mesh =
      test::box_mesh(Eigen::Vector3d(kLength, kWidth, kWidth), kWidth / 3.0);
  CorotatedSolverSettings settings;
  settings.linear_solver = LinearSolver::CHOLESKY;
  CorotatedSolver solver(mesh, ElementMaterials::uniform(mesh.tet_count(), {1e5, 0.3, 1000.0}),
                         settings);
  solver.set_dirichlet(bar_ends(mesh), stretch_and_twist(1.0));
  for (int stage = 1; stage <= 10; ++stage) {
    solver.set_time(0.1 * stage);
    const StepStats& stats = solver.solve_static(300, 1e-6);
    EXPECT_TRUE(stats.static_converged)
        << "stage " << stage << " after " << stats.static_iterations << " rounds";
  }
  // The far end reached its prescribed pose: stretched to 2.5 L.
  EXPECT_NEAR(solver.positions_matrix().col(0).maxCoeff(), 2.5 * kLength, 1e-12);
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
