#include "mgelastic/grid/corotated_dynamics.hpp"

#include <cmath>
#include <sstream>

#include "mgelastic/core/error.hpp"

namespace mgelastic::grid {
namespace {

template <int Dim>
ElasticityProblem<Dim> with_inertia(ElasticityProblem<Dim> problem, double inertia) {
  problem.inertia = inertia;
  return problem;
}

}  // namespace

template <int Dim>
CorotatedBackwardEuler<Dim>::CorotatedBackwardEuler(ElasticityProblem<Dim> problem,
                                                    const TimeStepOptions& options,
                                                    MultigridOptions multigrid,
                                                    CorotatedOptions corotated)
    : m_options((validate(options), options)),
      m_inertia(backward_euler_inertia(options)),
      m_multigrid(with_inertia(std::move(problem), m_inertia), multigrid, corotated) {
  allocate_step_state<Dim>(m_multigrid.solution_level(), m_static_rhs, m_velocity, m_previous);
}

template <int Dim>
void CorotatedBackwardEuler<Dim>::set_velocity(const VectorField& velocity) {
  sample_face_velocity<Dim>(m_multigrid.solution_level(), velocity, m_velocity);
}

template <int Dim>
void CorotatedBackwardEuler<Dim>::set_loads(ElasticityProblem<Dim> problem) {
  m_multigrid.set_loads(with_inertia(std::move(problem), m_inertia));
  // set_loads leaves the static right-hand side in b; each step builds its own b from it.
  assign_live(m_static_rhs, m_multigrid.solution_level().b, m_multigrid.solution_level().live);
}

template <int Dim>
void CorotatedBackwardEuler<Dim>::assemble_right_hand_side() {
  Level<Dim, double>& level = m_multigrid.solution_level();
  if (m_options.damping > 0) {
    for (auto& b : level.b) zero_live(b, level.live);
    m_multigrid.nonlinear_residual();
  }
  write_step_right_hand_side<Dim>(level, m_static_rhs, m_velocity, m_options, m_inertia);
}

template <int Dim>
CorotatedReport CorotatedBackwardEuler<Dim>::step(const VectorField& dirichlet) {
  Level<Dim, double>& level = m_multigrid.solution_level();
  const double dt = m_options.dt;
  assemble_right_hand_side();
  start_step<Dim>(level, m_velocity, dt, m_previous);
  m_multigrid.set_dirichlet_displacement(dirichlet);  // also back-substitutes tractions
  CorotatedReport report;
  try {
    report = m_options.vcycles_per_step > 0
                 ? m_multigrid.run_cycles(m_options.vcycles_per_step)
                 : m_multigrid.solve(m_options.tolerance, m_options.max_vcycles);
  } catch (const Error& e) {
    throw diverged_step(m_time, std::string(": ") + e.what());
  }
  update_face_velocity<Dim>(level, m_previous, dt, m_velocity);
  m_time += dt;
  return report;
}

template <int Dim>
double CorotatedBackwardEuler<Dim>::kinetic_energy() const {
  return face_kinetic_energy<Dim>(m_multigrid.solution_level(), m_velocity, m_options.density);
}

template class CorotatedBackwardEuler<2>;
template class CorotatedBackwardEuler<3>;

}  // namespace mgelastic::grid
