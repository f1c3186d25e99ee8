#pragma once
// Cantilever of length L along x with a square b x b section, clamped at the wall x = 0 (tet: the
// vertices on it; grid: the body continues one Dirichlet cell behind it, so the free length is L
// at every resolution, cantilever.cpp), under
// (a) a total tip force P = 10 N along -y on the face x = L (loads.forces with normal selection
// [1, 0, 0]) and (b) gravity g along -y.
//
// Timoshenko beam theory (I = b^4 / 12, A = b^2, G = E / (2 (1 + nu)), shear coefficient of a
// rectangle kappa = 10 (1 + nu) / (12 + 11 nu)):
//   tip force:  delta = P L^3 / (3 E I) + P L / (kappa G A)
//   gravity:    delta = q L^4 / (8 E I) + q L^2 / (2 kappa G A),   q = rho g A.
// A 3D clamp holds the whole end section (no Poisson contraction there, no warping), which the beam
// theory does not: the 3D solution is stiffer by a few percent (2-5 % for slender bars), so the
// converged 3D deflection lies a few percent below theory. The Richardson extrapolation of the
// three resolutions estimates the converged 3D value, and its distance from theory is that clamp
// effect (plus whatever the engine converges to).
//
// Measured: the tip deflection -u_y averaged over the face x = L (grid: 5 x 5 points on the face,
// trilinear lattice interpolation; tet: the mesh vertices on the face).
#include <string>
#include <vector>

#include "mgelastic/validation/convergence_series.hpp"

namespace mgelastic::validation {

struct Cantilever {
  double length = 1.0, thickness = 0.2;  // m
  // Density 100: the gravity deflection stays ~4 % of L, where the corotated tet engine is still
  // linear to ~0.1 % (at 1000 it sags 0.38 L and the corotated answer leaves linear theory by 13
  // %).
  double youngs_modulus = 1e6, poisson_ratio = 0.3, density = 100;
  double tip_force = 10.0;  // N, total along -y
  double gravity = 9.81;    // m/s^2, along -y

  double shear_coefficient() const;
  double tip_force_deflection() const;  // Timoshenko
  double gravity_deflection() const;    // Timoshenko
};

enum class CantileverLoad { TIP_FORCE, GRAVITY };

// One series: tip deflection for `engine` ("grid" or "tet") at `resolutions` cells (cubes) along
// the length.
ConvergenceSeries cantilever_study(const std::string& engine, const Cantilever& beam,
                                   CantileverLoad load, const std::vector<int>& resolutions);

}  // namespace mgelastic::validation
