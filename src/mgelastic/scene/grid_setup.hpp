#pragma once
// From a scene to the grid engine's problem (Sec. 5.1): the body is voxelized (cells that
// overlap it are interior), cells overlapping a constraint region become Dirichlet cells
// (fixed), and gravity loads the body with density * g.
#include "mgelastic/geometry/voxelization.hpp"
#include "mgelastic/grid/problem.hpp"
#include "mgelastic/scene/scene.hpp"

namespace mgelastic::scene {

struct GridSetup {
  grid::ElasticityProblem<3> problem;
  geometry::ShapePtr body;
  geometry::VoxelGrid voxels;
  std::size_t interior_cells = 0, dirichlet_cells = 0;
};

GridSetup build_grid_setup(const Scene& scene);

}  // namespace mgelastic::scene
