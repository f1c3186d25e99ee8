#pragma once
// Backward-Euler dynamics of the grid engine (Zhu et al. 2010, Sec. 8), in displacements u:
//   rho (v' - v) / dt = L u' + f + gamma L_0 v' - alpha rho v',   u' = u + dt v',
// with L u = div P (traction boundary stresses included, L_0 its homogeneous part), f the body
// force (the static right-hand side is b_static = -f), gamma the stiffness-proportional and
// alpha the mass-proportional (Rayleigh) damping coefficient. Eliminating v' and dividing by
// beta = 1 + gamma / dt gives the paper's "L u - c phi = b":
//   L u' - c u' = b,   c = rho (1 + alpha dt) / (dt (dt + gamma)),
//   b = (b_static + (gamma / dt) L u - (rho / dt) v) / beta - c u.
// The multigrid solves it like statics: -c I on the momentum rows of every level (the coarse
// levels get the same c, their equations being force densities and the restriction averaging),
// the distribution's pressure block -2 Lap + c/mu (distributive_smoother.hpp), the band rows
// with -c on their diagonal, c on the coarsest Cholesky diagonal. Pressure rows are unchanged.
// Velocities follow from positions, v' = (u' - u) / dt. Each step starts from u + dt v (the
// previous step extrapolated) and runs a fixed number of cycles or cycles to a tolerance.
//
// State: velocity() holds v on every face variable of the finest level, Dim arrays of
// lattice.size() entries (lattice.hpp layout), zero at inactive faces; the displacement (and
// pressure) is the multigrid solution (Multigrid::solution_level().x). With time() these are
// all that a checkpoint needs.
#include <array>
#include <functional>
#include <string>
#include <vector>

#include "mgelastic/core/error.hpp"
#include "mgelastic/grid/multigrid.hpp"

namespace mgelastic::grid {

struct TimeStepOptions {
  double dt = 1.0 / 30.0;     // step length (s)
  double density = 1000.0;    // rho (kg/m^3)
  double damping = 0.0;       // gamma (s), stiffness-proportional
  double mass_damping = 0.0;  // alpha (1/s), mass-proportional
  int vcycles_per_step = 1;   // fixed number of cycles per step; 0 = cycle to `tolerance`
  double tolerance = 1e-6;    // relative residual per step when vcycles_per_step = 0
  int max_vcycles = 50;       // cycle limit per step when vcycles_per_step = 0
  bool accelerate = false;    // FGMRES-accelerated cycles when cycling to the tolerance
};

// Throws mgelastic::Error naming the option unless it is in range.
void validate(const TimeStepOptions& options);

// The c of the step equation above.
double backward_euler_inertia(const TimeStepOptions& options);

// A step's carried arrays on `level`'s lattice: zero storage whose dead chunks are never written
// (live_chunks.hpp; the step's passes visit the live chunks only), static_rhs = level.b.
template <int Dim>
void allocate_step_state(const Level<Dim, double>& level,
                         std::array<FieldArray<double>, Dim + 1>& static_rhs,
                         std::array<FieldArray<double>, Dim>& velocity,
                         std::array<FieldArray<double>, Dim>& previous);

// The step's start: previous = u, then u += dt v at the interior faces (the warm start).
template <int Dim>
void start_step(Level<Dim, double>& level, const std::array<FieldArray<double>, Dim>& velocity,
                double dt, std::array<FieldArray<double>, Dim>& previous);

// Samples `velocity` at the face variables of `level` (0 at inactive faces) into `out`.
template <int Dim>
void sample_face_velocity(const Level<Dim, double>& level,
                          const std::function<Vec<Dim>(const Vec<Dim>&)>& velocity,
                          std::array<FieldArray<double>, Dim>& out);

// v' = (u' - u) / dt at the face variables (0 at inactive faces), from the level's u' and the
// step's starting displacement `previous`.
template <int Dim>
void update_face_velocity(const Level<Dim, double>& level,
                          const std::array<FieldArray<double>, Dim>& previous, double dt,
                          std::array<FieldArray<double>, Dim>& velocity);

// Kinetic energy (1/2) rho h^d sum v^2 over the interior face variables.
template <int Dim>
double face_kinetic_energy(const Level<Dim, double>& level,
                           const std::array<FieldArray<double>, Dim>& velocity, double density);

// The error of a step from time t whose solve failed with `reason`.
Error diverged_step(double time, const std::string& reason);

// Writes the step's b = (b_static + (gamma/dt) L u - (rho/dt) v) / beta - c u into the interior
// momentum rows of `level` (b_static elsewhere). With damping (gamma > 0) level.r must hold the
// residual of b = 0, r = -(L u - c u), from which L u = c u - r.
template <int Dim>
void write_step_right_hand_side(Level<Dim, double>& level,
                                const std::array<FieldArray<double>, Dim + 1>& static_rhs,
                                const std::array<FieldArray<double>, Dim>& velocity,
                                const TimeStepOptions& options, double inertia);

template <int Dim, typename Scalar>
class BackwardEuler {
 public:
  using VectorField = std::function<Vec<Dim>(const Vec<Dim>&)>;

  // `problem` is the static problem (body force, tractions, Dirichlet values at time 0); its
  // `inertia` is set from the options. Starts at rest at time 0.
  BackwardEuler(ElasticityProblem<Dim> problem, const TimeStepOptions& options,
                MultigridOptions multigrid = {});

  // Sets v at every face variable (component i sampled at u_i faces).
  void set_velocity(const VectorField& velocity);
  // Advances one step to time() + dt. `dirichlet` is the prescribed displacement at the new
  // time (empty: the Dirichlet values stay). Throws mgelastic::Error if the step diverges.
  SolveReport step(const VectorField& dirichlet = {});
  // The loads of `problem` (body force, boundary stresses, variable loads) act from the next
  // step on, without a hierarchy build (Multigrid::set_loads); the rest of `problem` must be the
  // constructor's. Displacement, velocity and clock carry on.
  void set_loads(ElasticityProblem<Dim> problem);

  double time() const { return m_time; }
  void set_time(double time) { m_time = time; }
  const TimeStepOptions& options() const { return m_options; }
  double inertia() const { return m_inertia; }
  std::array<FieldArray<double>, Dim>& velocity() { return m_velocity; }
  const std::array<FieldArray<double>, Dim>& velocity() const { return m_velocity; }
  Multigrid<Dim, Scalar>& multigrid() { return m_multigrid; }
  const Multigrid<Dim, Scalar>& multigrid() const { return m_multigrid; }
  // 1/2 rho h^d sum v^2 over the interior face variables (J).
  double kinetic_energy() const;

 private:
  void assemble_right_hand_side(Level<Dim, double>& level);

  TimeStepOptions m_options;
  double m_inertia = 0;
  Multigrid<Dim, Scalar> m_multigrid;
  std::array<FieldArray<double>, Dim + 1> m_static_rhs;  // b_static = -f on the finest level
  std::array<FieldArray<double>, Dim> m_velocity, m_previous;
  double m_time = 0;
};

}  // namespace mgelastic::grid
