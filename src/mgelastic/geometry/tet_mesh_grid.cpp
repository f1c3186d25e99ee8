#include "mgelastic/geometry/tet_mesh_grid.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "mgelastic/core/error.hpp"

namespace mgelastic::geometry {

namespace {

// The six Kuhn tetrahedra of the unit cube: corner bit b = x + 2y + 4z. Each walks from corner 0
// to corner 7 adding one axis at a time, in the order of one permutation of (x, y, z).
constexpr std::array<std::array<int, 4>, 6> kKuhnTets = {
    {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}}};

struct Lattice {
  Eigen::Vector3d origin;
  double h;
  Eigen::Vector3i cells;
  long point_id(int i, int j, int k) const {
    return i + static_cast<long>(cells.x() + 1) * (j + static_cast<long>(cells.y() + 1) * k);
  }
  Eigen::Vector3d point(int i, int j, int k) const { return origin + h * Eigen::Vector3d(i, j, k); }
};

Lattice make_cube_lattice(const Eigen::AlignedBox3d& bbox, double cell_size) {
  if (!(cell_size > 0.0) || !std::isfinite(cell_size))
    throw Error("cell size must be positive", ErrorContext{std::string(), -1, "cell_size"});
  if (bbox.isEmpty() || !bbox.min().allFinite() || !bbox.max().allFinite())
    throw Error("bounding box is empty or not finite", ErrorContext{std::string(), -1, "bbox"});
  Lattice lattice{bbox.min(), cell_size, Eigen::Vector3i::Ones()};
  double points = 1.0;
  for (int a = 0; a < 3; ++a) {
    // The small slack keeps an extent that is an exact multiple of h from gaining a cell.
    const double n = std::ceil(bbox.sizes()[a] / cell_size - 1e-9);
    lattice.cells[a] = static_cast<int>(std::max(1.0, std::min(n, 2e9)));
    points *= lattice.cells[a] + 1.0;
  }
  if (points > 2e9)
    throw Error("grid too fine (> 2^31 points)", ErrorContext{std::string(), -1, "cell_size"});
  return lattice;
}

bool keep_cube(const Lattice& lattice, const InsidePredicate& inside, int i, int j, int k,
               CubeSelection selection) {
  if (inside(lattice.point(i, j, k) + Eigen::Vector3d::Constant(0.5 * lattice.h))) return true;
  if (selection == CubeSelection::CENTER) return false;
  for (int b = 0; b < 8; ++b)
    if (inside(lattice.point(i + (b & 1), j + ((b >> 1) & 1), k + ((b >> 2) & 1)))) return true;
  return false;
}

}  // namespace

RegularTetGrid regular_tet_grid(const InsidePredicate& inside, const Eigen::AlignedBox3d& bbox,
                                double cell_size, CubeSelection selection) {
  const Lattice lattice = make_cube_lattice(bbox, cell_size);
  std::vector<int> compact(
      lattice.point_id(lattice.cells.x(), lattice.cells.y(), lattice.cells.z()) + 1, -1);
  std::vector<Eigen::Vector3i> grid_points;
  std::vector<std::array<int, 4>> tets;
  for (int k = 0; k < lattice.cells.z(); ++k)
    for (int j = 0; j < lattice.cells.y(); ++j)
      for (int i = 0; i < lattice.cells.x(); ++i) {
        if (!keep_cube(lattice, inside, i, j, k, selection)) continue;
        // Corners get compact vertex ids on first use, so unused grid points never appear.
        std::array<int, 8> corner;
        for (int b = 0; b < 8; ++b) {
          const Eigen::Vector3i g(i + (b & 1), j + ((b >> 1) & 1), k + ((b >> 2) & 1));
          int& id = compact[lattice.point_id(g.x(), g.y(), g.z())];
          if (id < 0) {
            id = static_cast<int>(grid_points.size());
            grid_points.push_back(g);
          }
          corner[b] = id;
        }
        for (const auto& tet : kKuhnTets)
          tets.push_back({corner[tet[0]], corner[tet[1]], corner[tet[2]], corner[tet[3]]});
      }
  if (tets.empty())
    throw Error("no grid cube lies inside the body", ErrorContext{std::string(), -1, "bbox"});
  RegularTetGrid grid;
  grid.cells = lattice.cells;
  grid.mesh.vertices.resize(static_cast<long>(grid_points.size()), 3);
  grid.vertex_grid_index.resize(static_cast<long>(grid_points.size()), 3);
  for (std::size_t v = 0; v < grid_points.size(); ++v) {
    const Eigen::Vector3i& g = grid_points[v];
    grid.mesh.vertices.row(v) = lattice.point(g.x(), g.y(), g.z()).transpose();
    grid.vertex_grid_index.row(v) = g.transpose();
  }
  grid.mesh.tets.resize(static_cast<long>(tets.size()), 4);
  for (std::size_t t = 0; t < tets.size(); ++t)
    for (int a = 0; a < 4; ++a) grid.mesh.tets(t, a) = tets[t][a];
  // Half of the Kuhn tetrahedra come out negatively oriented (odd permutations); the check
  // relabels them, so the result follows the positive-volume convention.
  check_tet_mesh(grid.mesh, TetMeshCheckOptions{}, "regular_tet_grid");
  return grid;
}

}  // namespace mgelastic::geometry
