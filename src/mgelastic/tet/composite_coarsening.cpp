#include "mgelastic/tet/composite_coarsening.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "mgelastic/core/disjoint_sets.hpp"
#include "mgelastic/core/error.hpp"

namespace mgelastic::tet {
namespace {

// Weights below this (relative to 1) are round-off of a vertex lying on a face/edge/corner.
constexpr double kZeroWeight = 1e-12;

// Grid indices are < 2^21 per axis (the covering grids are far smaller).
long long key(const Eigen::Vector3i& c) {
  return (static_cast<long long>(c[2]) << 42) | (static_cast<long long>(c[1]) << 21) | c[0];
}

Eigen::Vector3i corner_offset(int corner) {
  return Eigen::Vector3i(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
}

// DOF -> cells containing it (CSR transpose of cells.dofs).
std::pair<std::vector<int>, std::vector<int>> cells_of_dofs(const LevelCells& cells,
                                                            int dof_count) {
  std::vector<int> offsets(dof_count + 1, 0), entries(cells.dofs.size());
  for (const int v : cells.dofs) ++offsets[v + 1];
  for (int v = 0; v < dof_count; ++v) offsets[v + 1] += offsets[v];
  std::vector<int> fill(offsets.begin(), offsets.end() - 1);
  for (int c = 0; c < cells.cell_count(); ++c)
    for (int k = cells.dof_offsets[c]; k < cells.dof_offsets[c + 1]; ++k)
      entries[fill[cells.dofs[k]]++] = c;
  return {std::move(offsets), std::move(entries)};
}

// Incidences (cell, cube) of v's cells, as (cube key, incidence index), sorted by cube.
void incidences_at(int v, const LevelCells& cells, const std::vector<int>& offsets,
                   const std::vector<int>& cells_of, std::vector<std::pair<long long, int>>& out) {
  out.clear();
  for (int k = offsets[v]; k < offsets[v + 1]; ++k) {
    const int c = cells_of[k];
    for (int i = cells.cube_offsets[c]; i < cells.cube_offsets[c + 1]; ++i)
      out.emplace_back(key(cells.cubes[i]), i);
  }
  std::sort(out.begin(), out.end());
}

// Kuhn tetrahedron of the unit cube containing u (corners as bit patterns x + 2y + 4z) and its
// barycentric weights: ordering u's coordinates descending, the tet is 0, e_a, e_a + e_b, 1.
void kuhn_weights(const Eigen::Vector3d& u, std::array<int, 4>& corners,
                  std::array<double, 4>& weights) {
  std::array<int, 3> axis{0, 1, 2};
  std::sort(axis.begin(), axis.end(), [&](int a, int b) { return u[a] > u[b]; });
  corners = {0, 1 << axis[0], (1 << axis[0]) | (1 << axis[1]), 7};
  weights = {1.0 - u[axis[0]], u[axis[0]] - u[axis[1]], u[axis[1]] - u[axis[2]], u[axis[2]]};
}

}  // namespace

CompositeLevel composite_coarsening(const LevelCells& cells, int dof_count,
                                    const std::vector<char>& constrained,
                                    const LocalCoordinates& local, const HomeCube& home) {
  const auto [offsets, cells_of] = cells_of_dofs(cells, dof_count);
  const int incidence_count = static_cast<int>(cells.cubes.size());
  std::vector<int> cell_of_incidence(incidence_count);
  for (int c = 0; c < cells.cell_count(); ++c)
    for (int i = cells.cube_offsets[c]; i < cells.cube_offsets[c + 1]; ++i)
      cell_of_incidence[i] = c;
  // 1. Components: incidences of one cube whose cells share a DOF.
  DisjointSets pieces(incidence_count);
  std::vector<std::pair<long long, int>> around;
  for (int v = 0; v < dof_count; ++v) {
    incidences_at(v, cells, offsets, cells_of, around);
    for (std::size_t k = 1; k < around.size(); ++k)
      if (around[k].first == around[k - 1].first)
        pieces.unite(around[k].second, around[k - 1].second);
  }
  std::vector<int> component_of(incidence_count, -1), root_component(incidence_count, -1);
  std::vector<Eigen::Vector3i> component_cube;
  for (int i = 0; i < incidence_count; ++i) {
    int& component = root_component[pieces.find(i)];
    if (component < 0) {
      component = static_cast<int>(component_cube.size());
      component_cube.push_back(cells.cubes[i]);
    }
    component_of[i] = component;
  }
  const int component_count = static_cast<int>(component_cube.size());
  // 2. Corner copies (8 per component), merged per grid point where components meet at a DOF.
  DisjointSets copies(8 * component_count);
  std::vector<std::pair<long long, int>> corners;
  for (int v = 0; v < dof_count; ++v) {
    incidences_at(v, cells, offsets, cells_of, around);
    corners.clear();
    for (std::size_t k = 0; k < around.size(); ++k) {
      const int component = component_of[around[k].second];
      if (k > 0 && component == component_of[around[k - 1].second]) continue;
      for (int corner = 0; corner < 8; ++corner)
        corners.emplace_back(key(component_cube[component] + corner_offset(corner)),
                             8 * component + corner);
    }
    std::sort(corners.begin(), corners.end());
    for (std::size_t k = 1; k < corners.size(); ++k)
      if (corners[k].first == corners[k - 1].first)
        copies.unite(corners[k].second, corners[k - 1].second);
  }
  // 3. Rows of P on copies: the home cube's component of v, Kuhn weights there.
  std::vector<std::array<int, 4>> row_copies(dof_count);
  std::vector<std::array<double, 4>> row_weights(dof_count);
  for (int v = 0; v < dof_count; ++v) {
    incidences_at(v, cells, offsets, cells_of, around);
    if (around.empty())
      throw Error("DOF " + std::to_string(v) + " belongs to no cell overlapping a coarse cube",
                  ErrorContext{std::string(), -1, "TetHierarchy"});
    const long long preferred = key(home(v));
    int chosen = -1;
    double distance = std::numeric_limits<double>::infinity();
    for (const auto& [cube, incidence] : around) {
      if (cube == preferred) {
        chosen = incidence;
        break;
      }
      const Eigen::Vector3d u = local(v, cells.cubes[incidence]);
      const double d = (u - u.cwiseMax(0.0).cwiseMin(1.0)).norm();
      if (d < distance) {
        distance = d;
        chosen = incidence;
      }
    }
    const int component = component_of[chosen];
    const Eigen::Vector3d u = local(v, cells.cubes[chosen]).cwiseMax(0.0).cwiseMin(1.0);
    std::array<int, 4> corner;
    kuhn_weights(u, corner, row_weights[v]);
    for (int s = 0; s < 4; ++s) row_copies[v][s] = copies.find(8 * component + corner[s]);
  }
  // 4. Coarse DOFs: the copies some row weighs (before the Dirichlet rule, so that the numbering
  // does not depend on the constraints), numbered by root.
  std::vector<char> weighed(8 * component_count, 0);
  for (int v = 0; v < dof_count; ++v)
    for (int s = 0; s < 4; ++s)
      if (std::abs(row_weights[v][s]) >= kZeroWeight) weighed[row_copies[v][s]] = 1;
  std::vector<int> dof_of_root(8 * component_count, -1);
  CompositeLevel level;
  for (int r = 0; r < 8 * component_count; ++r)
    if (weighed[r] != 0) {
      dof_of_root[r] = static_cast<int>(level.points.size());
      level.points.push_back(component_cube[r / 8] + corner_offset(r % 8));
    }
  Prolongation& p = level.prolongation;
  p.coarse_vertex_count = static_cast<int>(level.points.size());
  p.vertices.resize(dof_count);
  p.weights.resize(dof_count);
  for (int v = 0; v < dof_count; ++v) {
    const bool dirichlet = !constrained.empty() && constrained[v] != 0;
    int fallback = -1;  // a weighed DOF of the row, for the zero-weight slots' index
    for (int s = 0; s < 4; ++s)
      if (std::abs(row_weights[v][s]) >= kZeroWeight) fallback = dof_of_root[row_copies[v][s]];
    for (int s = 0; s < 4; ++s) {
      const bool weighed = std::abs(row_weights[v][s]) >= kZeroWeight;
      p.vertices[v][s] = weighed ? dof_of_root[row_copies[v][s]] : fallback;
      p.weights[v][s] = weighed && !dirichlet ? row_weights[v][s] : 0.0;
    }
  }
  // 5. The components as cells of the coarse level (their weighed corners).
  for (int component = 0; component < component_count; ++component) {
    const std::size_t begin = level.cells.dofs.size();
    for (int corner = 0; corner < 8; ++corner) {
      const int dof = dof_of_root[copies.find(8 * component + corner)];
      if (dof >= 0) level.cells.dofs.push_back(dof);
    }
    if (level.cells.dofs.size() == begin) continue;
    level.cells.dof_offsets.push_back(static_cast<int>(level.cells.dofs.size()));
    level.cell_cubes.push_back(component_cube[component]);
  }
  return level;
}

}  // namespace mgelastic::tet
