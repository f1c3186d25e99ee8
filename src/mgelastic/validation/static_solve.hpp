#pragma once
// Static solves of a scene document with either engine, for the validation studies: the grid
// engine's linear mixed u/p multigrid (Zhu et al. 2010) and the tet engine's corotated static
// equilibrium (Georgii & Westermann 2008), each converged tightly so that what the studies measure
// is discretization error, not solver error.
//
// The Dirichlet variables (grid) / vertices (tet) of the scene's constraint regions may be given
// a prescribed displacement field g(x) in place of the regions' rigid motions: the studies pin a
// body by the analytic solution itself on small patches, which removes the rigid modes without
// perturbing the field.
#include <cstddef>
#include <functional>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "mgelastic/grid/node_fields.hpp"
#include "mgelastic/scene/grid_setup.hpp"
#include "mgelastic/scene/tet_setup.hpp"

namespace mgelastic::validation {

using DisplacementField = std::function<Eigen::Vector3d(const Eigen::Vector3d&)>;

struct GridStatic {
  scene::GridSetup setup;
  grid::NodeDisplacement u;  // nodal displacement of the finest lattice (node_fields.hpp)
  std::size_t unknowns = 0;
  bool converged = false;
  double seconds = 0.0;
};

// Linear static solve (double, Krylov-accelerated V(1,1) cycles to `tolerance` relative residual;
// double round-off ends the reduction near 5e-11 at 80 cells along the cantilever, growing as
// (L / h)^2, so 1e-10 was out of reach at 160).
GridStatic solve_grid_static(const nlohmann::json& document, const DisplacementField& dirichlet,
                             double tolerance = 1e-9);

// Trilinear u(x) of the grid solution (surface_interpolation.hpp).
Eigen::Vector3d grid_displacement(const GridStatic& run, const Eigen::Vector3d& x);

struct TetStatic {
  scene::TetSetup setup;
  Eigen::MatrixX3d displacement;  // per mesh vertex, N x 3
  std::size_t unknowns = 0;
  bool converged = false;
  double seconds = 0.0;
};

// Static equilibrium (rotation updates until the update is below `tolerance` of the largest
// displacement; PCG to the scene's tet.tolerance).
TetStatic solve_tet_static(const nlohmann::json& document, const DisplacementField& dirichlet,
                           double tolerance = 1e-10);

// Rest positions and displacements of the tet engine's embedded surface (tet/embedded_surface.hpp).
void tet_surface_displacement(const TetStatic& run, Eigen::MatrixX3d& rest,
                              Eigen::MatrixX3d& displacement);

}  // namespace mgelastic::validation
