#pragma once
// Reaction forces of the tet engine's constraints: on a Dirichlet vertex v the constraint applies
// R_v = -(f_el(x) + f_ext)_v (CorotatedSolver::unbalanced_forces), the force that holds the
// vertex where it is prescribed. Per constraint: sum of R_v over its vertices, and the moment
// sum (x_v - point) x R_v about `point` with x_v the vertex's current position.
// At static equilibrium the free vertices' unbalanced forces vanish (to the solve tolerance), so
// the reactions balance every applied load exactly: sum_c R_c + gravity + surface forces = 0
// (the lumped loads of the Dirichlet vertices included).
#include <vector>

#include "mgelastic/core/reaction.hpp"

namespace mgelastic::tet {

// `unbalanced` and `positions`: 3N, vertex-major. `vertex_constraint`: per vertex the constraint
// index in [0, points.size()) or -1 (free). `points`: the moment point of each constraint.
std::vector<Reaction> constraint_reactions(const Eigen::VectorXd& unbalanced,
                                           const Eigen::VectorXd& positions,
                                           const std::vector<int>& vertex_constraint,
                                           const std::vector<Eigen::Vector3d>& points);

}  // namespace mgelastic::tet
