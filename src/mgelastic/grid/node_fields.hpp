#pragma once
// Fields for output and for the embedded surface (Sec. 9.3), on the finest 3D lattice:
// displacements at lattice nodes (cell corners) averaged from the staggered u_i of the four
// faces that share the node (interior, Dirichlet or back-substituted traction values), and per
// cell the linear stress from the nodal field, with its von Mises value. Trilinear sampling of
// the nodal displacement moves embedded surface points with the lattice.
#include <functional>
#include <vector>

#include "mgelastic/grid/level.hpp"

namespace mgelastic::grid {

// Nodal displacement of the real lattice: (n+1)^3 nodes, x fastest, 3 components per node.
struct NodeDisplacement {
  IVec<3> nodes;
  double h = 1;
  Vec<3> origin;
  std::vector<double> values;
  Vec<3> at(int i, int j, int k) const;
  // Trilinear interpolation at a world point (clamped to the lattice).
  Vec<3> sample(const Vec<3>& x) const;
};

// `value(field, k)` returns the finest-level solution (Multigrid::solution); it is called from
// several threads at once.
template <typename Scalar>
NodeDisplacement node_displacement(const Level<3, Scalar>& level,
                                   const std::function<double(int, std::ptrdiff_t)>& value);

// Per real cell (x fastest): von Mises stress of the linear stress of the nodal field.
std::vector<double> von_mises_stress(const NodeDisplacement& u, const Material& material);

}  // namespace mgelastic::grid
