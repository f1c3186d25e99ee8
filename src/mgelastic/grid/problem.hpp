#pragma once
// A quasistatic linear-elasticity problem on a typed lattice (Zhu et al. 2010, Sec. 5.1):
//   div P + f = 0 in the interior cells, u = g on Dirichlet variables,
//   P N = t on traction boundaries, with P = mu (grad u + grad u^T) + lambda (div u) I.
// A backward-Euler step of the dynamics (Sec. 8) adds the inertia term: div P - c u = b.
// The engine works with displacements u (DESIGN.md): the same equations as the paper's
// positions phi = X + u without the constant (2 mu + d lambda) I, and float keeps its digits.
#include <functional>
#include <vector>

#include "mgelastic/grid/lattice.hpp"
#include "mgelastic/grid/material.hpp"

namespace mgelastic::grid {

// A force density concentrated on one u_component variable of the finest lattice (N/m^3),
// e.g. an embedded surface force distributed to the staggered grid (Sec. 9.2).
struct VariableLoad {
  int component = 0;
  std::ptrdiff_t face = 0;  // flat index of the face (lattice.hpp layout)
  double density = 0.0;
};

template <int Dim>
struct ElasticityProblem {
  Lattice<Dim> lattice;
  std::vector<CellType> cells;  // lattice.size() entries; ghost ring must stay EXTERIOR
  Material material;
  // Body force density f (N/m^3) at a point; empty means zero.
  std::function<Vec<Dim>(const Vec<Dim>&)> body_force;
  // Prescribed displacement g at a point; component i is sampled at u_i locations. Empty = 0.
  std::function<Vec<Dim>(const Vec<Dim>&)> dirichlet_displacement;
  // Value substituted for a boundary stress P_ij (Sec. 5.3) whose traction condition holds at
  // the given point (a traction face center, or the edge center for i != j). Empty = free.
  std::function<double(int i, int j, const Vec<Dim>&)> boundary_stress;
  // Extra force densities at individual variables (added to the body force).
  std::vector<VariableLoad> variable_loads;
  // The c >= 0 of a backward-Euler step (Sec. 8, backward_euler.hpp): every momentum equation
  // of every level reads L u - c u = b (N/m^4). 0 = statics. With c > 0 a body needs no
  // Dirichlet support (inertia makes the system definite).
  double inertia = 0.0;
};

}  // namespace mgelastic::grid
