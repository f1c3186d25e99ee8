#pragma once
// The patch test: a homogeneous strain u(x) = G x (G constant, symmetric, |G| ~ 1e-3) prescribed
// on the boundary of a box and no body force; every consistent discretization reproduces it
// exactly inside, so the error is round-off plus what the solver leaves.
//   grid: make_box_problem (DIRICHLET: a layer of Dirichlet cells all around an n^3 box) with
//         g = G x; error = max |u_i - (G x)_i| over the interior u variables.
//   tet:  a regular tet grid of the unit cube (n cubes across) with every boundary vertex held at
//         X + G X; error = max |u - G X| over the free vertices.
// The error is relative to max |G x| over the box.
#include <string>

#include "mgelastic/validation/convergence_series.hpp"

namespace mgelastic::validation {

struct PatchTestResult {
  std::string engine;
  int resolution = 0;
  double max_relative_error = 0.0;
  std::size_t unknowns = 0;
  bool converged = false;
};

PatchTestResult patch_test(const std::string& engine, int resolution, double poisson_ratio = 0.3);

}  // namespace mgelastic::validation
