#pragma once
// Reaction forces of the grid engine's constraints (finest level in double: the linear model's
// Multigrid::solution_level(), the co-rotated model's CorotatedMultigrid::solution_level()).
//
// Summing the momentum rows h^3 [sum_j (P_ij(+) - P_ij(-)) / h + f_i] = 0 over every interior u_i
// variable telescopes: a stress shared by two interior rows cancels, and what remains is the
// flux through the free body's boundary. There each stress is either eliminated (an incident
// cell exterior: its traction value, i.e. the applied surface loads, held in the rows'
// `constant`) or computed from the displacements because the row's neighbour across it is a
// Dirichlet variable: the flux the clamp passes into the free body. So the reaction of a
// constraint is
//   R_i = sum over interior rows e, stresses P_ij of e whose neighbour row is a Dirichlet variable
//         of the constraint:  +-h^2 P_ij   (+ on the row's upper side, - on its lower side),
// with P_ii = 2 mu d_i u_i - mu p at cell centers and P_ij = mu (d_j u_i + d_i u_j) at edges
// (stencil.hpp), and its moment is sum (location of the stress - point) x (force). By the
// telescoping sum, sum_c R_c + free_load = -h^3 sum_e r_e: the reactions balance the applied
// loads to the solver's residual. The loads that fall on Dirichlet variables (gravity on the
// constrained cells, surface-force shares there) are held by the clamp directly and appear in
// neither side. The moment takes the stress locations as the points of application, so it is
// first-order accurate in h (the force balance is exact).
// Co-rotated model: the same sum with the co-rotated stresses (corotated_operator.hpp) of the
// rotations of the current displacement, i.e. of the rows of the true non-linear residual the
// solve converged, so the force balance holds to that residual as well. The stress is the first
// Piola-Kirchhoff one (force per rest area), so the forces need no deformed areas; the moment
// takes the deformed stress locations (rest location + displacement there) as points of
// application, and the constraint's point stays where it was given (the rest centroid).
#include <functional>
#include <vector>

#include "mgelastic/core/reaction.hpp"
#include "mgelastic/grid/corotated_operator.hpp"
#include "mgelastic/grid/level.hpp"

namespace mgelastic::grid {

// `constraint_of(x)`: index in [0, points.size()) of the constraint holding the Dirichlet
// variable at face center x. `points`: the moment point of each constraint. Throws Error for a
// coarse level (fill weights or a relocated Dirichlet depth).
std::vector<Reaction> constraint_reactions(const Level<3, double>& level,
                                           const std::function<int(const Vec<3>&)>& constraint_of,
                                           const std::vector<Eigen::Vector3d>& points);

// Co-rotated model (see above): `sigma` the problem's boundary tractions (their traction
// conditions enter the stresses next to traction faces), `form` the rows' stress.
std::vector<Reaction> corotated_constraint_reactions(
    const Level<3, double>& level, const BoundaryStress<3>& sigma,
    const std::function<int(const Vec<3>&)>& constraint_of,
    const std::vector<Eigen::Vector3d>& points,
    CorotatedStress form = CorotatedStress::SYMMETRIZED);

// The applied loads on the free body as the rows see them (N): body forces and surface-force
// shares on interior variables plus the eliminated boundary stresses, sum over interior u rows of
// h^3 (constant - b).
Eigen::Vector3d free_load(const Level<3, double>& level);

}  // namespace mgelastic::grid
