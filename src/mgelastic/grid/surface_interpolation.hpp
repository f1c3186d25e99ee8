#pragma once
// Displacement of embedded surface points from the lattice's nodal displacement (Sec. 9.3).
//
// Data: NodeDisplacement u, nodes (i, j, k) at origin + h (i, j, k), x fastest, 3 components per
// node. A point x is clamped to the lattice; in the cell with lower node i = floor((x - o) / h)
// (the last cell for points on the upper faces) at local coordinates t in [0, 1]^3:
//
// TRILINEAR: u(x) = sum over the 8 corners of prod_a (1 - t_a or t_a) u_corner (as
//   NodeDisplacement::sample). Reproduces multilinear fields (affine included) exactly; only C0,
//   so the surface normals jump across cell faces.
// TRICUBIC: Lekien & Marsden (2005), the C1 tricubic whose 64 coefficients per cell match f,
//   f_x, f_y, f_z, f_xy, f_xz, f_yz, f_xyz at the 8 corners. Written in its equivalent tensor
//   Hermite form u(x) = sum over corners c, sum over alpha in {0,1}^3 of
//   prod_a H[c_a][alpha_a](t_a) (h D_a)^alpha_a u(c), with the cubic Hermite basis
//   H[0][0] = 2t^3 - 3t^2 + 1, H[1][0] = 3t^2 - 2t^3, H[0][1] = t^3 - 2t^2 + t, H[1][1] = t^3 -
//   t^2. The nodal derivatives are finite differences, mixed ones products of the 1D operators
//   (e.g. f_xy = D_x D_y f), with
//     h D g[m] = (g[m+1] - g[m-1]) / 2                    interior nodes,
//     h D g[0] = (-3 g[0] + 4 g[1] - g[2]) / 2            lattice border (one-sided, second order),
//     h D g[0] = h D g[1] = g[1] - g[0]                   when an axis has only 2 nodes.
//   Every cell sees the same nodal derivatives, so the interpolant is C1 across cell faces. Since
//   D is exact for quadratics, the interpolant reproduces exactly every polynomial of degree
//   <= 2 in each variable (x^2 y^2 z^2 included), up to the lattice border; a cubic term costs
//   an O(h^2) derivative error, so the error for smooth fields is O(h^3) (O(h^4) would need
//   exact derivatives). In the interior the 1D weights on nodes i-1..i+2 are Catmull-Rom's.
//
// Nodes outside the body: NodeDisplacement carries a value at every node (averaged from the
// active faces around it, zero where none is active) and no mask, so both methods use the values
// as they are. Trilinear reads only the corners of the cell holding x, which for a surface point
// are corners of an occupied cell and carry data. Tricubic also reads the next node outwards on
// each axis; near the boundary that node may hold a zero placeholder that bends the surface
// toward zero displacement. Padding the voxelization by one layer (Sec. 9.2, Fig. 17) gives
// every such node data.
#include <Eigen/Core>

#include "mgelastic/grid/node_fields.hpp"

namespace mgelastic::grid {

enum class SurfaceInterpolation { TRILINEAR, TRICUBIC };

using PointRows = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;  // N x 3

// u(x) for one point. Throws Error when the lattice has fewer than 2 nodes on an axis or the
// values do not hold 3 components per node.
Vec<3> interpolate_displacement(const NodeDisplacement& u, const Vec<3>& x,
                                SurfaceInterpolation method);

// deformed.row(p) = rest.row(p) + u(rest.row(p)) for every row, in parallel; deformed is resized
// to rest's shape and may be the same object as rest.
void displace_points(const NodeDisplacement& u, SurfaceInterpolation method, const PointRows& rest,
                     PointRows& deformed);

}  // namespace mgelastic::grid
