#include "mgelastic/scene/grid_setup.hpp"

#include "mgelastic/core/error.hpp"
#include "mgelastic/scene/build_shape.hpp"

namespace mgelastic::scene {

GridSetup build_grid_setup(const Scene& scene) {
  GridSetup setup;
  setup.body = build_shape(scene.geometry, scene.directory, scene.file, "/geometry");
  setup.voxels = geometry::voxelize(
      *setup.body,
      {.cell_size = scene.cell_size, .resolution = scene.resolution, .padding = scene.padding});
  const auto& v = setup.voxels;
  auto& p = setup.problem;
  p.lattice = grid::Lattice<3>(v.dims, v.cell_size, v.origin);
  p.material = {scene.youngs_modulus, scene.poisson_ratio};
  p.cells.assign(p.lattice.size(), grid::CellType::EXTERIOR);
  for (int k = 0; k < v.dims[2]; ++k)
    for (int j = 0; j < v.dims[1]; ++j)
      for (int i = 0; i < v.dims[0]; ++i)
        if (v.occupied[v.index(i, j, k)])
          p.cells[p.lattice.index(grid::IVec<3>(i + 1, j + 1, k + 1))] = grid::CellType::INTERIOR;
  for (std::size_t c = 0; c < scene.constraints.size(); ++c) {
    const std::string at = "/constraints/" + std::to_string(c) + "/region";
    const auto region = build_shape(scene.constraints[c].region, scene.directory, scene.file, at);
    const auto mask = geometry::overlapping_cells(v, *region);
    std::size_t selected = 0;
    for (int k = 0; k < v.dims[2]; ++k)
      for (int j = 0; j < v.dims[1]; ++j)
        for (int i = 0; i < v.dims[0]; ++i) {
          if (!mask[v.index(i, j, k)]) continue;
          selected += v.occupied[v.index(i, j, k)];
          p.cells[p.lattice.index(grid::IVec<3>(i + 1, j + 1, k + 1))] = grid::CellType::DIRICHLET;
        }
    if (selected == 0)
      throw Error("the region selects no cell of the body at this resolution",
                  ErrorContext{.file = scene.file, .pointer = at});
  }
  for (auto c : p.cells) {
    setup.interior_cells += c == grid::CellType::INTERIOR;
    setup.dirichlet_cells += c == grid::CellType::DIRICHLET;
  }
  if (setup.interior_cells == 0)
    throw Error("the geometry has no interior cell at this resolution",
                ErrorContext{.file = scene.file, .pointer = "/grid"});
  const Eigen::Vector3d load = scene.density * scene.gravity;
  p.body_force = [load](const grid::Vec<3>&) { return grid::Vec<3>(load); };
  return setup;
}

}  // namespace mgelastic::scene
