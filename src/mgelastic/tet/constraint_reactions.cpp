#include "mgelastic/tet/constraint_reactions.hpp"

#include "mgelastic/core/error.hpp"

namespace mgelastic::tet {

std::vector<Reaction> constraint_reactions(const Eigen::VectorXd& unbalanced,
                                           const Eigen::VectorXd& positions,
                                           const std::vector<int>& vertex_constraint,
                                           const std::vector<Eigen::Vector3d>& points) {
  const auto n = static_cast<Eigen::Index>(vertex_constraint.size());
  if (unbalanced.size() != 3 * n || positions.size() != 3 * n)
    throw Error("constraint_reactions: forces and positions need 3 entries per vertex");
  std::vector<Reaction> reactions(points.size());
  for (std::size_t c = 0; c < points.size(); ++c) reactions[c].point = points[c];
  for (Eigen::Index v = 0; v < n; ++v) {
    const int c = vertex_constraint[static_cast<std::size_t>(v)];
    if (c < 0) continue;
    if (c >= static_cast<int>(points.size()))
      throw Error("constraint_reactions: vertex constraint index out of range");
    const Eigen::Vector3d force = -unbalanced.segment<3>(3 * v);
    Reaction& r = reactions[static_cast<std::size_t>(c)];
    r.force += force;
    r.moment += (positions.segment<3>(3 * v) - r.point).cross(force);
  }
  return reactions;
}

}  // namespace mgelastic::tet
