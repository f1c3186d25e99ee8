#include "mgelastic/scene/grid_setup.hpp"

#include <limits>

#include "mgelastic/core/error.hpp"
#include "mgelastic/core/system_memory.hpp"
#include "mgelastic/grid/embedded_traction.hpp"
#include "mgelastic/grid/half_cell_body_force.hpp"
#include "mgelastic/scene/build_shape.hpp"
#include "mgelastic/scene/grid_memory.hpp"
#include "mgelastic/scene/render_surface.hpp"
#include "mgelastic/scene/surface_selection.hpp"

namespace mgelastic::scene {

bool GridSetup::animated() const {
  for (const auto& r : regions)
    if (!r.motion.is_fixed()) return true;
  return false;
}

namespace {

std::size_t deepest_region(const std::vector<GridSetup::Region>& regions, const grid::Vec<3>& x) {
  std::size_t deepest = 0;
  double depth = std::numeric_limits<double>::infinity();
  for (std::size_t r = 0; r < regions.size(); ++r) {
    const double d = regions[r].shape->signed_distance(x);
    if (d < depth) depth = d, deepest = r;
  }
  return deepest;
}

}  // namespace

int constraint_at(const GridSetup& setup, const grid::Vec<3>& x) {
  return static_cast<int>(deepest_region(setup.regions, x));
}

std::function<grid::Vec<3>(const grid::Vec<3>&)> dirichlet_displacement(const GridSetup& setup,
                                                                        double time) {
  if (!setup.animated()) return {};
  return [regions = setup.regions, time](const grid::Vec<3>& x) -> grid::Vec<3> {
    return regions[deepest_region(regions, x)].motion.displacement(x, time);
  };
}

// Each selected rest-surface triangle carries its share of a traction, pressure or total force
// at its centroid (one-point quadrature; triangles are a fraction of a cell). The problem holds
// no other variable loads or boundary stresses, so both are rebuilt from scratch.
void set_surface_loads(const Scene& scene, GridSetup& setup) {
  setup.problem.variable_loads.clear();
  setup.problem.boundary_stress = {};
  std::vector<grid::SurfaceForce<3>> forces;
  for (const TriangleForce& f :
       surface_load_forces(scene, setup.surface, "part of the body's surface"))
    forces.push_back({f.centroid, f.force, f.normal});
  setup.traction_triangles = forces.size();
  if (!forces.empty()) grid::apply_surface_forces(setup.problem, forces);
  // The half cells' weight wraps the stresses: again after each load change, which replaces them.
  if (scene.time.quasistatic) grid::add_half_cell_body_force(setup.problem);
}

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
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int k = 0; k < v.dims[2]; ++k)
      for (int j = 0; j < v.dims[1]; ++j)
        for (int i = 0; i < v.dims[0]; ++i) {
          if (!mask[v.index(i, j, k)]) continue;
          const std::ptrdiff_t cell = p.lattice.index(grid::IVec<3>(i + 1, j + 1, k + 1));
          if (v.occupied[v.index(i, j, k)]) {
            ++selected;
            centroid += p.lattice.cell_center(cell);
          }
          p.cells[cell] = grid::CellType::DIRICHLET;
        }
    setup.constraint_centroids.push_back(selected ? centroid / double(selected) : centroid);
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
  const Eigen::Vector3d load = scene.density * scene.gravity;
  p.body_force = [load](const grid::Vec<3>&) { return grid::Vec<3>(load); };
  set_surface_loads(scene, setup);  // after the body force: it wraps the half-cell term around
  return setup;
}

}  // namespace mgelastic::scene
