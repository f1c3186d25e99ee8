#pragma once
// From a scene to the grid engine's problem (Sec. 5.1): the body is voxelized (cells that
// overlap it are interior), cells overlapping a constraint region become Dirichlet cells
// (fixed or keyframed), gravity loads the body with density * g, and tractions on the part of
// the rest surface inside a region become surface forces distributed to the staggered variables
// (Sec. 9.2, embedded_traction.hpp).
#include "mgelastic/geometry/triangle_mesh.hpp"
#include "mgelastic/geometry/voxelization.hpp"
#include "mgelastic/grid/problem.hpp"
#include "mgelastic/scene/scene.hpp"

namespace mgelastic::scene {

struct GridSetup {
  grid::ElasticityProblem<3> problem;
  geometry::ShapePtr body;
  geometry::VoxelGrid voxels;
  std::size_t interior_cells = 0, dirichlet_cells = 0;
  // Constraint regions in scene order with their motions; a Dirichlet variable follows the
  // region it lies deepest in (smallest signed distance).
  struct Region {
    geometry::ShapePtr shape;
    KeyframedMotion motion;
  };
  std::vector<Region> regions;
  // Per constraint: centroid of its Dirichlet body cells (the moment point of its reaction).
  std::vector<Eigen::Vector3d> constraint_centroids;
  geometry::TriangleMesh surface;  // rest surface the lattice carries (render_surface.hpp)
  std::size_t traction_triangles = 0;
  bool animated() const;  // some region is keyframed
};

// The problem's dirichlet_displacement is that of time 0.
GridSetup build_grid_setup(const Scene& scene);

// Replaces the problem's surface loads (variable loads, boundary stresses) by those of the
// scene's loads.tractions, pressures and forces: at setup, and when a Simulation's loads change
// between steps (GridStepper hands the problem to the solver then). Quasistatic scenes get the
// half-cell body-force term around the new stresses (half_cell_body_force.hpp), as at setup; the
// body force must be set before.
void set_surface_loads(const Scene& scene, GridSetup& setup);

// Index into Scene::constraints of the region a Dirichlet variable at x follows (the one it lies
// deepest in).
int constraint_at(const GridSetup& setup, const grid::Vec<3>& x);

// Prescribed displacement of the Dirichlet variables at `time`.
std::function<grid::Vec<3>(const grid::Vec<3>&)> dirichlet_displacement(const GridSetup& setup,
                                                                        double time);

}  // namespace mgelastic::scene
