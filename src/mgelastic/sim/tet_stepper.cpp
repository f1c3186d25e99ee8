#include "mgelastic/sim/tet_stepper.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "mgelastic/core/error.hpp"
#include "mgelastic/core/timer.hpp"
#include "mgelastic/tet/embedded_surface.hpp"
#include "mgelastic/tet/polar_rotation.hpp"

namespace mgelastic::sim {
namespace {

// Rotation/solve rounds of one quasistatic frame. The frozen-rotation iteration of solve_static
// converges linearly, slower the more the body is twisted (~0.97 per round for a bar stretched
// 2.5x and turned once), so the cap is generous.
constexpr int kStaticRounds = 300;

std::string format_values(const std::vector<StepStats>& steps) {
  std::string text;
  char number[32];
  for (const StepStats& s : steps) {
    std::snprintf(number, sizeof number, "%s%.3e", text.empty() ? "" : " ", s.relative_residual);
    text += number;
  }
  return text;
}

void add(FrameStats& stats, const tet::StepStats& step) {
  stats.step_stats.push_back({.cycles = step.solve.iterations,
                              .relative_residual = step.solve.relative_residual,
                              .converged = step.solve.converged,
                              .seconds = step.solve_seconds + step.galerkin_seconds});
  stats.cycles += step.solve.iterations;
  stats.worst_residual = std::max(stats.worst_residual, step.solve.relative_residual);
  stats.converged = stats.converged && step.solve.converged;
  stats.rotate_seconds += step.rotate_seconds;
  stats.assemble_seconds += step.assemble_seconds;
  stats.solve_seconds += step.solve_seconds + step.galerkin_seconds;  // multigrid: Galerkin
}

}  // namespace

TetStepper::TetStepper(const scene::Scene& scene) : m_scene(&scene) {
  Timer timer;
  m_setup = scene::build_tet_setup(scene);
  m_solver =
      std::make_unique<tet::CorotatedSolver>(m_setup.mesh, m_setup.materials, m_setup.settings);
  m_solver->set_dirichlet(m_setup.dirichlet_vertices, m_setup.motion);
  if (m_setup.surface_forces.size() > 0) m_solver->set_surface_forces(m_setup.surface_forces);
  m_surface_rest =
      tet::embedded_positions(m_setup.surface, m_setup.mesh.vertices, m_setup.mesh.tets);
  for (const auto& c : scene.constraints) m_motions.push_back(c.motion);
  m_setup_seconds = timer.seconds();
}

FrameStats TetStepper::advance_frame(int frame, double& attempt_time) {
  const scene::Scene& s = *m_scene;
  // Frame k shows the state at time (k + 1) dt, as in the grid engine.
  const double time = (frame + 1) * s.time.dt;
  attempt_time = time;
  FrameStats stats;
  stats.frame = frame;
  stats.time = time;
  try {
    if (s.time.quasistatic) {
      // The clock decides where the keyframed regions are; the previous equilibrium is the start.
      m_solver->set_time(time);
      const tet::StepStats& step = m_solver->solve_static(kStaticRounds, s.tet.tolerance);
      add(stats, step);
      stats.steps = step.static_iterations;
      stats.converged = stats.converged && step.static_converged;
    } else {
      for (int k = 0; k < s.time.substeps; ++k) {
        add(stats, m_solver->step());
        ++stats.steps;
      }
    }
  } catch (const Error& e) {
    // Which step of the frame failed, and how the steps before it went.
    const std::string history = stats.step_stats.empty()
                                    ? std::string()
                                    : ", after " + std::to_string(stats.steps) +
                                          " good step(s) with relative residuals " +
                                          format_values(stats.step_stats);
    std::string where = e.context().pointer;
    where = (where.empty() ? "" : where + ": ") + e.reason();
    const std::string step = s.time.quasistatic ? std::string("static solve")
                                                : "step " + std::to_string(m_solver->step_count());
    throw Error(where + " (" + step + history + ")", ErrorContext{.pointer = "tet solver"});
  }
  m_time = time;
  return stats;
}

// Checkpoint state: CorotatedState as arrays ("tet.rotations" holds the quaternions' x, y, z, w
// per element).
void TetStepper::save(io::Checkpoint& c, const std::vector<io::NamedArray>& attachments) const {
  const tet::CorotatedState state = m_solver->state();
  const auto add = [&](const char* name, const Eigen::VectorXd& v) {
    c.add<double>(name, std::span(v.data(), static_cast<std::size_t>(v.size())));
  };
  add("tet.positions", state.positions);
  add("tet.velocities", state.velocities);
  add("tet.accelerations", state.accelerations);
  std::vector<double> rotations;
  for (const Eigen::Quaterniond& q : state.rotations)
    rotations.insert(rotations.end(), q.coeffs().data(), q.coeffs().data() + 4);
  c.add<double>("tet.rotations", rotations);
  const std::vector<double> clock{state.time};
  c.add<double>("tet.time", clock);
  const std::vector<std::int64_t> counters{state.have_acceleration ? 1 : 0, state.steps};
  c.add<std::int64_t>("tet.counters", counters);
  c.arrays.insert(c.arrays.end(), attachments.begin(), attachments.end());
}

void TetStepper::restore(const io::Checkpoint& c) {
  tet::CorotatedState state = m_solver->state();
  const auto get = [&](const char* name, Eigen::VectorXd& v) {
    const std::vector<double> values = c.get<double>(name, v.size());
    v = Eigen::Map<const Eigen::VectorXd>(values.data(), v.size());
  };
  get("tet.positions", state.positions);
  get("tet.velocities", state.velocities);
  get("tet.accelerations", state.accelerations);
  const std::vector<double> rotations =
      c.get<double>("tet.rotations", 4 * static_cast<std::int64_t>(state.rotations.size()));
  for (std::size_t e = 0; e < state.rotations.size(); ++e)
    state.rotations[e].coeffs() = Eigen::Map<const Eigen::Vector4d>(rotations.data() + 4 * e);
  state.time = c.get<double>("tet.time", 1)[0];
  const std::vector<std::int64_t> counters = c.get<std::int64_t>("tet.counters", 2);
  state.have_acceleration = counters[0] != 0;
  state.steps = counters[1];
  try {
    m_solver->restore(state);
  } catch (const Error& e) {
    throw Error("corrupted checkpoint: " + e.reason(), ErrorContext{.file = c.source});
  }
  m_time = c.time;
}

void TetStepper::set_region_pose(std::size_t region, const Eigen::Vector3d& translate,
                                 const Eigen::Quaterniond& rotate) {
  require(region < m_motions.size(), "region",
          "no constraint region " + std::to_string(region) + " (the scene has " +
              std::to_string(m_motions.size()) + ")");
  m_motions[region] = scene::KeyframedMotion(m_motions[region].pivot(),
                                             {scene::RigidKeyframe{0.0, translate, rotate}});
  apply_motion();
}

void TetStepper::loads_changed() {
  m_setup.surface_forces = scene::tet_surface_forces(*m_scene, m_setup.mesh);
  m_solver->set_surface_forces(m_setup.surface_forces);
}

void TetStepper::apply_motion() {
  auto motions = std::make_shared<const std::vector<scene::KeyframedMotion>>(m_motions);
  auto owner = std::make_shared<const std::vector<int>>(m_setup.vertex_constraint);
  m_solver->set_dirichlet(m_setup.dirichlet_vertices,
                          [owner, motions](int vertex, const Eigen::Vector3d& rest, double time) {
                            const int c = (*owner)[vertex];
                            return c < 0 ? rest : (*motions)[c].position(rest, time);
                          });
}

// Von Mises stress of the corotated linear stress per element: strain eps = sym(R^T F) - I with
// R the polar rotation of F at the current positions (independent of the rotation method the
// solver used), sigma = lambda tr(eps) I + 2 mu eps, von Mises = sqrt(3/2 dev(sigma):dev(sigma)).
namespace {

// Cauchy stress of element e: the linear law on the unrotated strain (the corotated model).
Eigen::Matrix3d element_stress(const tet::TetBody& body, const Eigen::VectorXd& positions, int e) {
  const Eigen::Matrix3d f =
      tet::deformation_gradient(body.corners(e, positions), body.rest_edge_inverse(e));
  const Eigen::Matrix3d unrotated = tet::polar_rotation(f).transpose() * f;
  const Eigen::Matrix3d strain =
      0.5 * (unrotated + unrotated.transpose()) - Eigen::Matrix3d::Identity();
  const Eigen::Vector2d lame = tet::lame_parameters(body.materials()[e]);
  return lame[0] * strain.trace() * Eigen::Matrix3d::Identity() + 2.0 * lame[1] * strain;
}

}  // namespace

Eigen::MatrixXd TetStepper::von_mises() const {
  Eigen::MatrixXd stress(m_solver->body().element_count(), 1);
  for (int e = 0; e < stress.rows(); ++e) stress(e, 0) = von_mises_of(e);
  return stress;
}

double TetStepper::von_mises_of(int element) const {
  const Eigen::Matrix3d sigma = element_stress(m_solver->body(), m_solver->positions(), element);
  const Eigen::Matrix3d deviator = sigma - sigma.trace() / 3.0 * Eigen::Matrix3d::Identity();
  return std::sqrt(1.5 * deviator.squaredNorm());
}

double TetStepper::pressure(int element) const {
  return -element_stress(m_solver->body(), m_solver->positions(), element).trace() / 3.0;
}

io::SurfaceVertices TetStepper::surface_vertices() const {
  return tet::embedded_positions(m_setup.surface, m_solver->positions_matrix(), m_setup.mesh.tets);
}

}  // namespace mgelastic::sim
