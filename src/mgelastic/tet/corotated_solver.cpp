#include "mgelastic/tet/corotated_solver.hpp"

#include <Eigen/CholmodSupport>
#include <algorithm>
#include <cmath>
#include <string>

#include "mgelastic/core/blas_threads.hpp"
#include "mgelastic/core/error.hpp"
#include "mgelastic/core/timer.hpp"

namespace mgelastic::tet {

struct CorotatedSolver::Cholesky {
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> factorization;
  bool analyzed = false;
};

namespace {

[[noreturn]] void fail(const std::string& reason, const std::string& where) {
  throw Error(reason, ErrorContext{std::string(), -1, where});
}

void check_settings(const CorotatedSolverSettings& s) {
  if (!(s.time_step > 0.0) || !std::isfinite(s.time_step))
    fail("must be positive and finite", "time_step");
  if (!(s.rayleigh_alpha >= 0.0) || !(s.rayleigh_beta >= 0.0))
    fail("Rayleigh coefficients must be non-negative", "rayleigh");
  if (!s.gravity.allFinite()) fail("must be finite", "gravity");
  if (!(s.pcg.tolerance > 0.0) || s.pcg.max_iterations < 1)
    fail("tolerance must be positive, max_iterations >= 1", "pcg");
  if (s.vcycles < 0) fail("must be >= 0", "vcycles");
  if (s.multigrid.pre_smoothing < 0 || s.multigrid.post_smoothing < 0)
    fail("smoothing sweeps must be >= 0", "multigrid");
  if (s.newton.max_iterations < 1 || !(s.newton.max_step > 0.0))
    fail("max_iterations >= 1 and max_step > 0 required", "newton");
}

}  // namespace

CorotatedSolver::CorotatedSolver(const geometry::TetMesh& mesh, const ElementMaterials& materials,
                                 const CorotatedSolverSettings& settings)
    : m_settings((check_settings(settings), settings)),
      m_body(mesh, materials),
      m_rotations(m_body, settings.rotation_method, settings.newton),
      m_assembler(m_body),
      m_constrained(m_body.vertex_count(), 0),
      m_x(m_body.rest_positions()),
      m_v(Eigen::VectorXd::Zero(m_x.size())),
      m_a(Eigen::VectorXd::Zero(m_x.size())),
      m_cholesky(std::make_unique<Cholesky>()) {
  set_dirichlet({});
}

CorotatedSolver::~CorotatedSolver() = default;

void CorotatedSolver::set_dirichlet(std::vector<int> vertices, DirichletMotion motion) {
  // Vertices without elements have no mass and no stiffness: fixing them keeps A regular.
  std::fill(m_constrained.begin(), m_constrained.end(), 1);
  const Eigen::MatrixX4i& tets = m_body.tets();
  for (int e = 0; e < tets.rows(); ++e)
    for (int a = 0; a < 4; ++a) m_constrained[tets(e, a)] = 0;
  for (int v : vertices) {
    if (v < 0 || v >= m_body.vertex_count())
      fail("vertex " + std::to_string(v) + " out of range", "dirichlet");
    m_constrained[v] = 1;
  }
  m_dirichlet = std::move(vertices);
  m_motion = std::move(motion);
  m_multigrid.reset();  // the hierarchy's Dirichlet levels follow the constrained set
}

Eigen::VectorXd CorotatedSolver::prescribed_positions(double time) const {
  Eigen::VectorXd target = m_x;
  const Eigen::VectorXd& rest = m_body.rest_positions();
  for (int v : m_dirichlet) {
    const Eigen::Vector3d x0 = rest.segment<3>(3 * v);
    target.segment<3>(3 * v) = m_motion ? m_motion(v, x0, time) : x0;
    if (!target.segment<3>(3 * v).allFinite())
      fail("prescribed position is not finite", "dirichlet: vertex " + std::to_string(v));
  }
  return target;
}

Eigen::VectorXd CorotatedSolver::gravity_forces() const {
  Eigen::VectorXd f(m_x.size());
  for (int v = 0; v < m_body.vertex_count(); ++v)
    f.segment<3>(3 * v) = m_body.vertex_mass()[v] * m_settings.gravity;
  if (m_surface_forces.size() == f.size()) f += m_surface_forces;
  return f;
}

Eigen::VectorXd CorotatedSolver::unbalanced_forces() const {
  return m_assembler.elastic_forces(m_rotations, m_x) + gravity_forces();
}

void CorotatedSolver::set_surface_forces(Eigen::VectorXd forces) {
  if (forces.size() != m_x.size() || !forces.allFinite())
    fail("must have 3 finite entries per vertex", "surface forces");
  m_surface_forces = std::move(forces);
}

void CorotatedSolver::update_operator(StepStats& stats) {
  Timer timer;
  stats.rotation = m_rotations.update(m_x);
  stats.rotate_seconds = timer.seconds();
  timer.restart();
  m_assembler.assemble(m_rotations);
  stats.assemble_seconds = timer.seconds();
}

void CorotatedSolver::solve(double mass_scale, double stiffness_scale, const Eigen::VectorXd& known,
                            Eigen::VectorXd& b, Eigen::VectorXd& unknown, StepStats& stats) {
  Timer timer;
  const StepSystem system(m_assembler.stiffness(), m_body.vertex_mass(), mass_scale,
                          stiffness_scale, m_constrained);
  system.eliminate(known, b);
  for (int v = 0; v < m_body.vertex_count(); ++v)
    if (m_constrained[v]) unknown.segment<3>(3 * v) = known.segment<3>(3 * v);
  if (m_settings.linear_solver == LinearSolver::PCG) {
    stats.solve = solve_pcg(system, b, unknown, m_settings.pcg);
  } else if (m_settings.linear_solver == LinearSolver::MULTIGRID ||
             m_settings.linear_solver == LinearSolver::MG_PCG) {
    Timer update;
    if (!m_multigrid) {
      geometry::TetMesh mesh;
      mesh.vertices = positions_matrix();
      const Eigen::VectorXd& rest = m_body.rest_positions();
      for (int v = 0; v < m_body.vertex_count(); ++v)
        mesh.vertices.row(v) = rest.segment<3>(3 * v).transpose();
      mesh.tets = m_body.tets();
      m_multigrid = std::make_unique<TetMultigrid>(mesh, m_constrained, m_assembler.stiffness(),
                                                   m_settings.multigrid);
    }
    m_multigrid->update(m_assembler.stiffness(), m_body.vertex_mass(), mass_scale, stiffness_scale);
    stats.galerkin_seconds += update.seconds();
    timer.restart();
    solve_multigrid(b, unknown, stats);
  } else {
    const Eigen::SparseMatrix<double> a = system.to_sparse();
    const SingleThreadedBlas one_blas_thread;  // results independent of the thread count
    if (!m_cholesky->analyzed) m_cholesky->factorization.analyzePattern(a);
    m_cholesky->analyzed = true;
    m_cholesky->factorization.factorize(a);
    if (m_cholesky->factorization.info() != Eigen::Success)
      fail("sparse Cholesky failed (matrix not positive definite?)", "CHOLESKY");
    unknown = m_cholesky->factorization.solve(b);
    Eigen::VectorXd ax;
    system.apply(unknown, ax);
    stats.solve = {0, (ax - b).norm() / std::max(b.norm(), 1e-300), true};
  }
  if (!unknown.allFinite()) fail("linear solve produced non-finite values", "solve");
  stats.solve_seconds = timer.seconds();
}

void CorotatedSolver::solve_multigrid(const Eigen::VectorXd& b, Eigen::VectorXd& unknown,
                                      StepStats& stats) {
  const PcgSettings& pcg = m_settings.pcg;
  if (m_settings.linear_solver == LinearSolver::MG_PCG) {
    stats.solve = m_multigrid->solve_pcg(b, unknown, pcg);
  } else if (m_settings.vcycles > 0) {
    for (int c = 0; c < m_settings.vcycles; ++c) m_multigrid->cycle(b, unknown);
    Eigen::VectorXd r;
    m_multigrid->residual(b, unknown, r);
    const double relative = r.norm() / std::max(b.norm(), 1e-300);
    stats.solve = {m_settings.vcycles, relative, true};  // a fixed count is the contract
  } else {
    const MultigridResult result =
        m_multigrid->solve(b, unknown, pcg.tolerance, pcg.max_iterations);
    stats.solve = {result.cycles, result.relative_residual, result.converged};
  }
}

void CorotatedSolver::step_implicit_euler(StepStats& stats) {
  const double h = m_settings.time_step;
  Eigen::VectorXd b = m_assembler.elastic_forces(m_rotations, m_x) + gravity_forces();
  b *= h;
  for (int v = 0; v < m_body.vertex_count(); ++v)
    b.segment<3>(3 * v) += m_body.vertex_mass()[v] * m_v.segment<3>(3 * v);
  const Eigen::VectorXd known = (prescribed_positions(m_time + h) - m_x) / h;
  solve(1.0 + h * m_settings.rayleigh_alpha, h * h + h * m_settings.rayleigh_beta, known, b, m_v,
        stats);
  m_x += h * m_v;
}

void CorotatedSolver::step_newmark(StepStats& stats) {
  const double h = m_settings.time_step;
  const double alpha = m_settings.rayleigh_alpha;
  const double beta = m_settings.rayleigh_beta;
  const Eigen::VectorXd& mass = m_body.vertex_mass();
  // Damping force C v = alpha M v + beta K~ v with the freshly assembled K~.
  const auto damping = [&](const Eigen::VectorXd& v) {
    Eigen::VectorXd kv;
    m_assembler.stiffness().multiply(v, kv);
    kv *= beta;
    for (int i = 0; i < m_body.vertex_count(); ++i)
      kv.segment<3>(3 * i) += alpha * mass[i] * v.segment<3>(3 * i);
    return kv;
  };
  if (!m_have_acceleration) {
    // Initial acceleration from the equation of motion at t = 0 (lumped M is diagonal).
    const Eigen::VectorXd f =
        m_assembler.elastic_forces(m_rotations, m_x) + gravity_forces() - damping(m_v);
    for (int i = 0; i < m_body.vertex_count(); ++i)
      m_a.segment<3>(3 * i) = m_constrained[i] ? Eigen::Vector3d::Zero()
                                               : Eigen::Vector3d(f.segment<3>(3 * i) / mass[i]);
    m_have_acceleration = true;
  }
  const Eigen::VectorXd x_predicted = m_x + h * m_v + 0.25 * h * h * m_a;
  const Eigen::VectorXd v_predicted = m_v + 0.5 * h * m_a;
  Eigen::VectorXd b = m_assembler.elastic_forces(m_rotations, x_predicted) + gravity_forces() -
                      damping(v_predicted);
  const Eigen::VectorXd known = (prescribed_positions(m_time + h) - x_predicted) * (4.0 / (h * h));
  solve(1.0 + 0.5 * h * alpha, 0.25 * h * h + 0.5 * h * beta, known, b, m_a, stats);
  m_x = x_predicted + 0.25 * h * h * m_a;
  m_v = v_predicted + 0.5 * h * m_a;
}

const StepStats& CorotatedSolver::step() {
  Timer total;
  StepStats stats;
  update_operator(stats);
  if (m_settings.integrator == Integrator::IMPLICIT_EULER) {
    step_implicit_euler(stats);
  } else {
    step_newmark(stats);
  }
  if (!m_x.allFinite() || !m_v.allFinite())
    fail("step " + std::to_string(m_steps) + " produced non-finite positions", "step");
  m_time += m_settings.time_step;
  ++m_steps;
  stats.total_seconds = total.seconds();
  m_stats = stats;
  return m_stats;
}

double CorotatedSolver::free_residual_norm(const Eigen::VectorXd& x, StepStats& stats) {
  Timer timer;
  m_rotations.update(x);
  stats.rotate_seconds += timer.seconds();
  timer.restart();
  Eigen::VectorXd f = m_assembler.elastic_forces(m_rotations, x) + gravity_forces();
  for (int v = 0; v < m_body.vertex_count(); ++v)
    if (m_constrained[v]) f.segment<3>(3 * v).setZero();
  stats.assemble_seconds += timer.seconds();
  return f.norm();
}

const StepStats& CorotatedSolver::solve_static(int max_iterations, double tolerance) {
  if (m_dirichlet.empty())
    fail("needs Dirichlet vertices (a free body has no equilibrium)", "static");
  Timer total;
  StepStats stats;
  const Eigen::VectorXd target = prescribed_positions(m_time);
  const Eigen::VectorXd& rest = m_body.rest_positions();
  int pcg_iterations = 0;
  for (stats.static_iterations = 1; stats.static_iterations <= max_iterations;
       ++stats.static_iterations) {
    StepStats round;
    update_operator(round);
    Eigen::VectorXd b = m_assembler.elastic_forces(m_rotations, m_x) + gravity_forces();
    double residual = 0.0;
    if (stats.static_iterations > 1) {
      for (int v = 0; v < m_body.vertex_count(); ++v)
        if (!m_constrained[v]) residual += b.segment<3>(3 * v).squaredNorm();
      residual = std::sqrt(residual);
    }
    Eigen::VectorXd dx = Eigen::VectorXd::Zero(m_x.size());
    solve(0.0, 1.0, target - m_x, b, dx, round);
    // With the rotations frozen, dx is a Picard step: under large rotations it can overshoot
    // into a 2-cycle (x flips between two states). From the second round on (the first places
    // the Dirichlet vertices, which must move all the way) halve the step until the free
    // residual force decreases.
    double step = 1.0;
    if (stats.static_iterations > 1)
      for (int halvings = 0;
           halvings < 10 && free_residual_norm(m_x + step * dx, round) >= residual; ++halvings)
        step *= 0.5;
    m_x += step * dx;
    // Every round costs a full rotate/assemble/solve: report the sums, not the last round.
    stats.rotate_seconds += round.rotate_seconds;
    stats.assemble_seconds += round.assemble_seconds;
    stats.solve_seconds += round.solve_seconds;
    stats.galerkin_seconds += round.galerkin_seconds;
    stats.rotation = round.rotation;
    stats.solve = round.solve;
    pcg_iterations += round.solve.iterations;
    stats.solve.iterations = pcg_iterations;
    // Converged when the full Picard step (not the damped one) is small.
    const double scale = std::max((m_x - rest).lpNorm<Eigen::Infinity>(), 1e-300);
    if (dx.lpNorm<Eigen::Infinity>() <= tolerance * scale) {
      stats.static_converged = true;
      break;
    }
  }
  stats.static_iterations = std::min(stats.static_iterations, max_iterations);
  m_v.setZero();
  m_a.setZero();
  m_have_acceleration = false;
  stats.total_seconds = total.seconds();
  m_stats = stats;
  return m_stats;
}

void CorotatedSolver::set_time(double time) {
  if (!std::isfinite(time)) fail("must be finite", "time");
  m_time = time;
}

Eigen::MatrixX3d CorotatedSolver::positions_matrix() const {
  Eigen::MatrixX3d p(m_body.vertex_count(), 3);
  for (int v = 0; v < m_body.vertex_count(); ++v) p.row(v) = m_x.segment<3>(3 * v).transpose();
  return p;
}

void CorotatedSolver::set_state(const Eigen::VectorXd& positions,
                                const Eigen::VectorXd& velocities) {
  if (positions.size() != m_x.size() || velocities.size() != m_v.size())
    fail("state vectors need 3 entries per vertex", "state");
  if (!positions.allFinite() || !velocities.allFinite()) fail("state must be finite", "state");
  m_x = positions;
  m_v = velocities;
  m_have_acceleration = false;
}

CorotatedState CorotatedSolver::state() const {
  return {m_x, m_v, m_a, m_rotations.quaternions(), m_have_acceleration, m_time, m_steps};
}

void CorotatedSolver::restore(const CorotatedState& state) {
  set_state(state.positions, state.velocities);
  if (state.accelerations.size() != m_a.size() || !state.accelerations.allFinite())
    fail("accelerations need 3 finite entries per vertex", "state");
  set_time(state.time);
  m_rotations.set_quaternions(state.rotations);
  m_a = state.accelerations;
  m_have_acceleration = state.have_acceleration;
  m_steps = state.steps;
}

double CorotatedSolver::kinetic_energy() const {
  double energy = 0.0;
  for (int v = 0; v < m_body.vertex_count(); ++v)
    energy += 0.5 * m_body.vertex_mass()[v] * m_v.segment<3>(3 * v).squaredNorm();
  return energy;
}

double CorotatedSolver::elastic_energy() const {
  return m_assembler.elastic_energy(m_rotations, m_x);
}

double CorotatedSolver::gravity_energy() const {
  double energy = 0.0;
  const Eigen::VectorXd& rest = m_body.rest_positions();
  for (int v = 0; v < m_body.vertex_count(); ++v)
    energy -= m_body.vertex_mass()[v] *
              m_settings.gravity.dot(m_x.segment<3>(3 * v) - rest.segment<3>(3 * v));
  return energy;
}

}  // namespace mgelastic::tet
