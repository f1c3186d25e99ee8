// CorotatedSolver::state()/restore(): the checkpoint contract of `mgelastic run --resume`.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <vector>

#include "mgelastic/core/error.hpp"
#include "mgelastic/tet/corotated_solver.hpp"
#include "tet/tet_test_support.hpp"

namespace mgelastic::tet {
namespace {

using test::kMaterial;

// A bar clamped at x = 0, sagging and swinging under gravity: large rotations, so the energy
// rotation fit's warm starts matter, and Newmark carries accelerations from step to step.
struct SaggingBar {
  geometry::TetMesh mesh = test::box_mesh(Eigen::Vector3d(1, 0.2, 0.2), 0.1);
  CorotatedSolverSettings settings;
  SaggingBar() {
    settings.integrator = Integrator::NEWMARK;
    settings.rotation_method = RotationMethod::ENERGY_MINIMIZATION;
    settings.gravity = Eigen::Vector3d(0, -9.81, 0);
    settings.time_step = 0.02;
  }
  std::unique_ptr<CorotatedSolver> solver() const {
    auto s = std::make_unique<CorotatedSolver>(
        mesh, ElementMaterials::uniform(mesh.tet_count(), kMaterial), settings);
    std::vector<int> clamped;
    for (int v = 0; v < mesh.vertex_count(); ++v)
      if (mesh.vertices(v, 0) < 1e-9) clamped.push_back(v);
    s->set_dirichlet(clamped);
    return s;
  }
};

Eigen::VectorXd run(CorotatedSolver& solver, int steps) {
  for (int i = 0; i < steps; ++i) solver.step();
  return solver.positions();
}

// Exact equality on purpose: a resumed run must repeat the uninterrupted one bit for bit.
TEST(CorotatedState, RestoredSolverContinuesBitIdentically) {
  const SaggingBar bar;
  auto original = bar.solver();
  run(*original, 6);
  const CorotatedState saved = original->state();
  const Eigen::VectorXd uninterrupted = run(*original, 6);

  auto resumed = bar.solver();
  resumed->restore(saved);
  EXPECT_EQ(resumed->step_count(), 6);
  EXPECT_EQ(resumed->time(), saved.time);
  const Eigen::VectorXd continued = run(*resumed, 6);
  ASSERT_TRUE(continued.allFinite());
  EXPECT_TRUE(continued == uninterrupted) << (continued - uninterrupted).norm();
}

// Negative control: the rotations and accelerations are part of the state; dropping either
// changes the continuation.
TEST(CorotatedState, RotationsAndAccelerationsAreNeeded) {
  const SaggingBar bar;
  auto original = bar.solver();
  run(*original, 6);
  const CorotatedState saved = original->state();
  const Eigen::VectorXd uninterrupted = run(*original, 6);

  CorotatedState without_rotations = saved;
  std::fill(without_rotations.rotations.begin(), without_rotations.rotations.end(),
            Eigen::Quaterniond::Identity());
  auto a = bar.solver();
  a->restore(without_rotations);
  EXPECT_FALSE(run(*a, 6) == uninterrupted);

  CorotatedState without_accelerations = saved;
  without_accelerations.have_acceleration = false;
  auto b = bar.solver();
  b->restore(without_accelerations);
  EXPECT_FALSE(run(*b, 6) == uninterrupted);
}

TEST(CorotatedState, RestoreRejectsWrongSizesAndNonUnitRotations) {
  const SaggingBar bar;
  auto solver = bar.solver();
  CorotatedState state = solver->state();
  state.accelerations.resize(3);
  EXPECT_THROW(solver->restore(state), Error);
  state = solver->state();
  state.rotations[0] = Eigen::Quaterniond(2, 0, 0, 0);
  EXPECT_THROW(solver->restore(state), Error);
  state = solver->state();
  state.rotations.pop_back();
  EXPECT_THROW(solver->restore(state), Error);
}

}  // namespace
}  // namespace mgelastic::tet
