#pragma once
// The body force of the half cells outside the traction conditions (quasistatic problems).
//
// A traction face has no momentum equation: its value is back-substituted from P_ii = sigma,
// imposed at the boundary cell's center, half a cell inside the face (Sec. 5.3). The body
// force of the half cell between that center and the face then acts nowhere, so a body loses a
// first-order share of its weight ((n - 1) / n of it arrives at the supports for n cells
// across). The momentum balance of that half cell, dP_ii/dx_i + f_i = 0, gives the stress the
// center must carry:
//   P_ii(center) = sigma + sign (h / 2) f_i,   sign = +1 at an upper face (body below it),
// which this substitutes for the boundary stress, so that the whole weight reaches the supports.
// Dynamics keep the plain condition: the half cell's inertia is lost with its force, and a free
// fall stays exact only with both gone.
#include "mgelastic/grid/problem.hpp"

namespace mgelastic::grid {

// Wraps problem.boundary_stress (no change without a body force or with inertia > 0).
template <int Dim>
void add_half_cell_body_force(ElasticityProblem<Dim>& problem);

}  // namespace mgelastic::grid
