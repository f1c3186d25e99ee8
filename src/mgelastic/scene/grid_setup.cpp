#include "mgelastic/scene/grid_setup.hpp"

#include <limits>

#include "mgelastic/core/error.hpp"
#include "mgelastic/core/system_memory.hpp"
#include "mgelastic/grid/embedded_traction.hpp"
#include "mgelastic/scene/build_shape.hpp"
#include "mgelastic/scene/grid_memory.hpp"
#include "mgelastic/scene/render_surface.hpp"

namespace mgelastic::scene {

bool GridSetup::animated() const {
  for (const auto& r : regions)
    if (!r.motion.is_fixed()) return true;
  return false;
}

std::function<grid::Vec<3>(const grid::Vec<3>&)> dirichlet_displacement(const GridSetup& setup,
                                                                        double time) {
  if (!setup.animated()) return {};
  return [regions = setup.regions, time](const grid::Vec<3>& x) -> grid::Vec<3> {
    std::size_t deepest = 0;
    double depth = std::numeric_limits<double>::infinity();
    for (std::size_t r = 0; r < regions.size(); ++r) {
      const double d = regions[r].shape->signed_distance(x);
      if (d < depth) depth = d, deepest = r;
    }
    return regions[deepest].motion.displacement(x, time);
  };
}

namespace {

// Each rest-surface triangle whose centroid lies in a traction region carries traction * area
// at its centroid (one-point quadrature; triangles are a fraction of a cell).
void add_tractions(const Scene& scene, GridSetup& setup) {
  std::vector<grid::SurfaceForce<3>> forces;
  const auto& V = setup.surface.vertices;
  const auto& F = setup.surface.triangles;
  for (std::size_t t = 0; t < scene.tractions.size(); ++t) {
    const std::string at = "/loads/tractions/" + std::to_string(t) + "/region";
    const auto region = build_shape(scene.tractions[t].region, scene.directory, scene.file, at);
    std::size_t selected = 0;
    for (Eigen::Index f = 0; f < F.rows(); ++f) {
      const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
      const Eigen::Vector3d centroid = (a + b + c) / 3.0;
      const Eigen::Vector3d area_normal = 0.5 * (b - a).cross(c - a);
      const double area = area_normal.norm();
      if (area == 0 || !region->contains(centroid)) continue;
      forces.push_back({centroid, area * scene.tractions[t].traction, area_normal / area});
      ++selected;
    }
    if (selected == 0)
      throw Error("the region contains no part of the body's surface",
                  ErrorContext{.file = scene.file, .pointer = at});
    setup.traction_triangles += selected;
  }
  if (!forces.empty()) grid::apply_surface_forces(setup.problem, forces);
}

}  // namespace

GridSetup build_grid_setup(const Scene& scene) {
  if (!scene.material_regions.empty())
    throw Error("per-region materials are supported by the tet engine only",
                ErrorContext{.file = scene.file, .pointer = "/material/regions"});
  GridSetup setup;
  setup.body = build_shape(scene.geometry, scene.directory, scene.file, "/geometry");
  const geometry::VoxelizeOptions voxelize_options{
      .cell_size = scene.cell_size, .resolution = scene.resolution, .padding = scene.padding};
  // Refused before anything of the lattice's size is allocated.
  const SystemMemory memory = available_memory();
  check_grid_size(scene,
                  geometry::voxel_lattice(setup.body->bounding_box(), voxelize_options).cells,
                  memory.bytes, memory.source);
  setup.voxels = geometry::voxelize(*setup.body, voxelize_options);
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
    setup.regions.push_back({region, scene.constraints[c].motion});
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
  p.dirichlet_displacement = dirichlet_displacement(setup, 0.0);
  setup.surface = rest_surface(scene, *setup.body, v.cell_size);
  add_tractions(scene, setup);
  const Eigen::Vector3d load = scene.density * scene.gravity;
  p.body_force = [load](const grid::Vec<3>&) { return grid::Vec<3>(load); };
  return setup;
}

}  // namespace mgelastic::scene
