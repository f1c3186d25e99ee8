#pragma once
// The resultant a constraint (a Dirichlet region) exerts on the body: the force the clamp applies
// and its moment about a stated point. Both engines report one per constraint
// (grid/constraint_reactions.hpp, tet/constraint_reactions.hpp); at equilibrium the reactions
// balance the applied loads: sum of forces + loads = 0.
#include <Eigen/Core>

namespace mgelastic {

struct Reaction {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   // N, on the body
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();  // N m, about `point`
  Eigen::Vector3d point = Eigen::Vector3d::Zero();   // m
};

}  // namespace mgelastic
