#pragma once
// Backward-Euler dynamics (Sec. 8, backward_euler.hpp) with the co-rotational model (Sec. 7):
// each step solves L[u'] u' - c u' = b with the co-rotated operator, the rotations refreshed every
// k cycles (CorotatedMultigrid) and carried over from the previous step as its first frozen
// rotations. b = (b_static + (gamma/dt) L u - (rho/dt) v) / beta - c u, L u the non-linear
// co-rotated force of the previous displacement. State: as BackwardEuler (face velocities and
// the finest level's x).
#include <array>
#include <functional>
#include <vector>

#include "mgelastic/grid/backward_euler.hpp"
#include "mgelastic/grid/corotated_multigrid.hpp"

namespace mgelastic::grid {

template <int Dim>
class CorotatedBackwardEuler {
 public:
  using VectorField = std::function<Vec<Dim>(const Vec<Dim>&)>;

  CorotatedBackwardEuler(ElasticityProblem<Dim> problem, const TimeStepOptions& options,
                         MultigridOptions multigrid = {}, CorotatedOptions corotated = {});

  void set_velocity(const VectorField& velocity);
  // Replaces the loads from the next step on, without a hierarchy build
  // (CorotatedMultigrid::set_loads; BackwardEuler::set_loads): the step's static right-hand
  // side comes from `problem`, whose other members must be those of the build.
  void set_loads(ElasticityProblem<Dim> problem);
  // Advances one step; throws mgelastic::Error naming the time when the step diverges.
  CorotatedReport step(const VectorField& dirichlet = {});

  double time() const { return m_time; }
  void set_time(double time) { m_time = time; }
  std::array<FieldArray<double>, Dim>& velocity() { return m_velocity; }
  const std::array<FieldArray<double>, Dim>& velocity() const { return m_velocity; }
  CorotatedMultigrid<Dim>& multigrid() { return m_multigrid; }
  const CorotatedMultigrid<Dim>& multigrid() const { return m_multigrid; }
  double kinetic_energy() const;

 private:
  void assemble_right_hand_side();

  TimeStepOptions m_options;
  double m_inertia = 0;
  CorotatedMultigrid<Dim> m_multigrid;
  std::array<FieldArray<double>, Dim + 1> m_static_rhs;
  std::array<FieldArray<double>, Dim> m_velocity, m_previous;
  double m_time = 0;
};

}  // namespace mgelastic::grid
