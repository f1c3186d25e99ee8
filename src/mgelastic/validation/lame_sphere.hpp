#pragma once
// Hollow sphere under internal pressure (Lamé): inner radius a, outer radius b, pressure p on
// r = a, r = b traction-free. The radial displacement is
//   u_r(r) = A r + B / r^2,   A = p a^3 (1 - 2 nu) / (E (b^3 - a^3)),
//                             B = p a^3 b^3 (1 + nu) / (2 E (b^3 - a^3)).
// Neither engine has sliding (roller) constraints, so the whole sphere is solved: six small
// patches on the outer surface (boxes of edge 2.2 h around (+-b, 0, 0), (0, +-b, 0), (0, 0, +-b))
// are Dirichlet with the analytic displacement itself, which removes the rigid modes and leaves
// the radial field as it is. The pressure is loads.pressures[] on the surface inside the sphere of
// radius (a + b) / 2 (the inner surface), p / E = 1e-4 so the corotated tet engine stays linear.
//
// Measured: the mean radial displacement over the engine's surface vertices (grid: marching-cubes
// surface, trilinear lattice interpolation; tet: the input surface embedded in the tets) near
// r = a and near r = b, patches (and a margin of one cell) left out, against the mean of the
// analytic u_r at the same vertices' rest radii.
#include <vector>

#include "mgelastic/validation/convergence_series.hpp"

namespace mgelastic::validation {

struct LameSphere {
  double inner_radius = 0.5, outer_radius = 1.0;
  double pressure = 100.0;  // Pa
  double youngs_modulus = 1e6, poisson_ratio = 0.3;

  double radial_displacement(double r) const;
};

// Two series (u_r at r = a, u_r at r = b) for `engine` ("grid" or "tet") at `resolutions` cells
// (cubes) across the outer diameter.
std::vector<ConvergenceSeries> lame_sphere_study(const std::string& engine,
                                                 const LameSphere& sphere,
                                                 const std::vector<int>& resolutions);

}  // namespace mgelastic::validation
