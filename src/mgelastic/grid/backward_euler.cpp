#include "mgelastic/grid/backward_euler.hpp"

#include <cmath>
#include <sstream>

#include "mgelastic/core/error.hpp"
#include "mgelastic/grid/live_chunks.hpp"
#include "mgelastic/grid/residual.hpp"

namespace mgelastic::grid {
namespace {

[[noreturn]] void reject(const std::string& key, double value, const std::string& expected) {
  std::ostringstream text;
  text.precision(17);
  text << "must be " << expected << " (got " << value << ")";
  throw Error(text.str(), ErrorContext{.pointer = "time/" + key});
}

template <int Dim>
ElasticityProblem<Dim> with_inertia(ElasticityProblem<Dim> problem, double inertia) {
  problem.inertia = inertia;
  return problem;
}

}  // namespace

void validate(const TimeStepOptions& o) {
  if (!(std::isfinite(o.dt) && o.dt > 0)) reject("dt", o.dt, "a positive finite number");
  if (!(std::isfinite(o.density) && o.density > 0))
    reject("density", o.density, "a positive finite number");
  if (!(std::isfinite(o.damping) && o.damping >= 0))
    reject("damping", o.damping, "a finite number >= 0");
  if (!(std::isfinite(o.mass_damping) && o.mass_damping >= 0))
    reject("mass_damping", o.mass_damping, "a finite number >= 0");
  if (o.vcycles_per_step < 0) reject("vcycles_per_step", o.vcycles_per_step, ">= 0");
  if (o.vcycles_per_step == 0 && !(o.tolerance > 0 && o.tolerance < 1))
    reject("tolerance", o.tolerance, "in (0, 1) when cycling to a tolerance");
  if (o.vcycles_per_step == 0 && o.max_vcycles < 1)
    reject("max_vcycles", o.max_vcycles, ">= 1 when cycling to a tolerance");
}

double backward_euler_inertia(const TimeStepOptions& o) {
  return o.density * (1.0 + o.mass_damping * o.dt) / (o.dt * (o.dt + o.damping));
}

template <int Dim>
void allocate_step_state(const Level<Dim, double>& level,
                         std::array<FieldArray<double>, Dim + 1>& static_rhs,
                         std::array<FieldArray<double>, Dim>& velocity,
                         std::array<FieldArray<double>, Dim>& previous) {
  for (int f = 0; f <= Dim; ++f) {
    assign_zeros_sparse(static_rhs[f], level.size(), level.live);
    assign_live(static_rhs[f], level.b[f], level.live);
  }
  for (int i = 0; i < Dim; ++i) {
    assign_zeros_sparse(velocity[i], level.size(), level.live);
    assign_zeros_sparse(previous[i], level.size(), level.live);
  }
}

template <int Dim>
void start_step(Level<Dim, double>& level, const std::array<FieldArray<double>, Dim>& velocity,
                double dt, std::array<FieldArray<double>, Dim>& previous) {
  const auto n = static_cast<std::ptrdiff_t>(level.size());
  parallel_for_each_live_chunk(level.live, n, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
    for (int i = 0; i < Dim; ++i) {
      std::copy(level.x[i].begin() + lo, level.x[i].begin() + hi, previous[i].begin() + lo);
      for (std::ptrdiff_t k = lo; k < hi; ++k)
        if (level.kind(i, k) == VarKind::INTERIOR) level.x[i][k] += dt * velocity[i][k];
    }
  });
}

template <int Dim>
void sample_face_velocity(const Level<Dim, double>& level,
                          const std::function<Vec<Dim>(const Vec<Dim>&)>& velocity,
                          std::array<FieldArray<double>, Dim>& out) {
  for (int i = 0; i < Dim; ++i)
    for_each_live_chunk(level.live, 0, static_cast<std::ptrdiff_t>(level.size()),
                        [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
                          for (std::ptrdiff_t k = lo; k < hi; ++k)
                            out[i][k] = level.kind(i, k) == VarKind::INACTIVE
                                            ? 0.0
                                            : velocity(level.lattice.face_center(i, k))[i];
                        });
}

template <int Dim>
void write_step_right_hand_side(Level<Dim, double>& level,
                                const std::array<FieldArray<double>, Dim + 1>& static_rhs,
                                const std::array<FieldArray<double>, Dim>& velocity,
                                const TimeStepOptions& options, double inertia) {
  const double dt = options.dt, gamma = options.damping, c = inertia;
  const double beta = 1.0 + gamma / dt;
  const auto n = static_cast<std::ptrdiff_t>(level.size());
  // Live chunks only (the dead ones hold zeros in every array here), in parallel.
  parallel_for_each_live_chunk(level.live, n, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
    for (int i = 0; i < Dim; ++i) {
      for (std::ptrdiff_t k = lo; k < hi; ++k) {
        if (level.kind(i, k) != VarKind::INTERIOR) {
          level.b[i][k] = static_rhs[i][k];
          continue;
        }
        const double u = level.x[i][k];
        const double damping_force = gamma > 0 ? (gamma / dt) * (c * u - level.r[i][k]) : 0.0;
        level.b[i][k] =
            (static_rhs[i][k] + damping_force - (options.density / dt) * velocity[i][k]) / beta -
            c * u;
      }
    }
    std::copy(static_rhs[Dim].begin() + lo, static_rhs[Dim].begin() + hi,
              level.b[Dim].begin() + lo);
  });
}

template <int Dim>
void update_face_velocity(const Level<Dim, double>& level,
                          const std::array<FieldArray<double>, Dim>& previous, double dt,
                          std::array<FieldArray<double>, Dim>& velocity) {
  parallel_for_each_live_chunk(level.live, static_cast<std::ptrdiff_t>(level.size()),
                               [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
                                 for (int i = 0; i < Dim; ++i)
                                   for (std::ptrdiff_t k = lo; k < hi; ++k)
                                     velocity[i][k] = level.kind(i, k) == VarKind::INACTIVE
                                                          ? 0.0
                                                          : (level.x[i][k] - previous[i][k]) / dt;
                               });
}

template <int Dim>
double face_kinetic_energy(const Level<Dim, double>& level,
                           const std::array<FieldArray<double>, Dim>& velocity, double density) {
  double sum = 0;
  for (int i = 0; i < Dim; ++i)
    for (std::size_t k = 0; k < level.size(); ++k)
      if (level.kind(i, k) == VarKind::INTERIOR) sum += velocity[i][k] * velocity[i][k];
  return 0.5 * density * std::pow(level.lattice.h, Dim) * sum;
}

Error diverged_step(double time, const std::string& reason) {
  std::ostringstream text;
  text << "the time step from t = " << time << " s diverged" << reason;
  return Error(text.str(), ErrorContext{.pointer = "time"});
}

#define MGELASTIC_INSTANTIATE(D)                                                                   \
  template void sample_face_velocity<D>(const Level<D, double>&,                                   \
                                        const std::function<Vec<D>(const Vec<D>&)>&,               \
                                        std::array<FieldArray<double>, D>&);                       \
  template void allocate_step_state<D>(                                                            \
      const Level<D, double>&, std::array<FieldArray<double>, D + 1>&,                             \
      std::array<FieldArray<double>, D>&, std::array<FieldArray<double>, D>&);                     \
  template void start_step<D>(Level<D, double>&, const std::array<FieldArray<double>, D>&, double, \
                              std::array<FieldArray<double>, D>&);                                 \
  template void write_step_right_hand_side<D>(                                                     \
      Level<D, double>&, const std::array<FieldArray<double>, D + 1>&,                             \
      const std::array<FieldArray<double>, D>&, const TimeStepOptions&, double);                   \
  template void update_face_velocity<D>(const Level<D, double>&,                                   \
                                        const std::array<FieldArray<double>, D>&, double,          \
                                        std::array<FieldArray<double>, D>&);                       \
  template double face_kinetic_energy<D>(const Level<D, double>&,                                  \
                                         const std::array<FieldArray<double>, D>&, double);
MGELASTIC_INSTANTIATE(2)
MGELASTIC_INSTANTIATE(3)
#undef MGELASTIC_INSTANTIATE

template <int Dim, typename Scalar>
BackwardEuler<Dim, Scalar>::BackwardEuler(ElasticityProblem<Dim> problem,
                                          const TimeStepOptions& options,
                                          MultigridOptions multigrid)
    : m_options((validate(options), options)),
      m_inertia(backward_euler_inertia(options)),
      m_multigrid(with_inertia(std::move(problem), m_inertia), multigrid) {
  allocate_step_state<Dim>(m_multigrid.solution_level(), m_static_rhs, m_velocity, m_previous);
}

template <int Dim, typename Scalar>
void BackwardEuler<Dim, Scalar>::set_velocity(const VectorField& velocity) {
  sample_face_velocity<Dim>(m_multigrid.solution_level(), velocity, m_velocity);
}

template <int Dim, typename Scalar>
void BackwardEuler<Dim, Scalar>::set_loads(ElasticityProblem<Dim> problem) {
  m_multigrid.set_loads(with_inertia(std::move(problem), m_inertia));
  // set_loads leaves the static right-hand side in b; each step builds its own b from it.
  assign_live(m_static_rhs, m_multigrid.solution_level().b, m_multigrid.solution_level().live);
}

template <int Dim, typename Scalar>
void BackwardEuler<Dim, Scalar>::assemble_right_hand_side(Level<Dim, double>& level) {
  if (m_options.damping > 0) {
    for (auto& b : level.b) zero_live(b, level.live);
    compute_residual(level);
  }
  write_step_right_hand_side<Dim>(level, m_static_rhs, m_velocity, m_options, m_inertia);
}

template <int Dim, typename Scalar>
SolveReport BackwardEuler<Dim, Scalar>::step(const VectorField& dirichlet) {
  Level<Dim, double>& level = m_multigrid.solution_level();
  const double dt = m_options.dt;
  assemble_right_hand_side(level);
  // Warm start: the previous step's displacement moved on by its velocity.
  start_step<Dim>(level, m_velocity, dt, m_previous);
  m_multigrid.set_dirichlet_displacement(dirichlet);  // also back-substitutes tractions
  SolveReport report;
  try {
    if (m_options.vcycles_per_step > 0) {
      report = m_multigrid.run_cycles(m_options.vcycles_per_step);
    } else if (m_options.accelerate) {
      report = m_multigrid.solve_accelerated(m_options.tolerance, m_options.max_vcycles);
    } else {
      report = m_multigrid.solve(m_options.tolerance, m_options.max_vcycles);
    }
  } catch (const Error& e) {
    throw diverged_step(m_time, std::string(": ") + e.what());
  }
  if (!std::isfinite(report.residuals.back()))
    throw diverged_step(m_time, " (non-finite residual); try a smaller time.dt or more substeps");
  update_face_velocity<Dim>(level, m_previous, dt, m_velocity);
  m_time += dt;
  return report;
}

template <int Dim, typename Scalar>
double BackwardEuler<Dim, Scalar>::kinetic_energy() const {
  return face_kinetic_energy<Dim>(m_multigrid.solution_level(), m_velocity, m_options.density);
}

template class BackwardEuler<2, float>;
template class BackwardEuler<2, double>;
template class BackwardEuler<3, float>;
template class BackwardEuler<3, double>;

}  // namespace mgelastic::grid
