#include "mgelastic/tet/tet_hierarchy.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_map>

#include "mgelastic/core/error.hpp"
#include "mgelastic/tet/composite_coarsening.hpp"

namespace mgelastic::tet {
namespace {

[[noreturn]] void fail_hierarchy(const std::string& reason) {
  throw Error(reason, ErrorContext{std::string(), -1, "TetHierarchy"});
}

// Cube grid of level 1 (cube size h, origin at the fine bounding box's minimum).
struct CubeGrid {
  Eigen::Vector3d origin;
  double h = 0.0;
  Eigen::Vector3i cells;
  Eigen::Vector3i cube_of(const Eigen::Vector3d& p) const {
    Eigen::Vector3i c;
    for (int a = 0; a < 3; ++a)
      c[a] = std::clamp(static_cast<int>(std::floor((p[a] - origin[a]) / h)), 0, cells[a] - 1);
    return c;
  }
  long long key(const Eigen::Vector3i& c) const {
    return (static_cast<long long>(c[2]) * cells[1] + c[1]) * cells[0] + c[0];
  }
};

CubeGrid cube_grid(const Eigen::AlignedBox3d& box, double h) {
  CubeGrid grid;
  grid.origin = box.min();
  grid.h = h;
  for (int a = 0; a < 3; ++a)
    grid.cells[a] = std::max(1, static_cast<int>(std::ceil(box.sizes()[a] / h)));
  return grid;
}

// Separating-axis test of a tetrahedron against the closed cube [lo, lo + h]^3 (touching counts,
// so a vertex on a cube face belongs to the cells of both cubes).
bool tet_overlaps_cube(const Eigen::Matrix<double, 3, 4>& corners, const Eigen::Vector3d& lo,
                       double h) {
  const Eigen::Matrix<double, 3, 4> p = corners.colwise() - (lo.array() + 0.5 * h).matrix();
  const double slack = 1e-9 * h;
  const auto separates = [&](const Eigen::Vector3d& axis) {
    const double length = axis.norm();
    if (length <= 1e-14 * h * h) return false;  // parallel edges: no axis
    const Eigen::Vector4d projection = p.transpose() * axis;
    const double radius = 0.5 * h * axis.cwiseAbs().sum() + slack * length;
    return projection.minCoeff() > radius || projection.maxCoeff() < -radius;
  };
  std::array<Eigen::Vector3d, 6> edges;
  int e = 0;
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b) edges[e++] = p.col(b) - p.col(a);
  for (int a = 0; a < 3; ++a)
    if (separates(Eigen::Vector3d::Unit(a))) return false;
  for (int f = 0; f < 4; ++f) {  // face opposite corner f
    const int i = (f + 1) % 4, j = (f + 2) % 4, k = (f + 3) % 4;
    if (separates((p.col(j) - p.col(i)).cross(p.col(k) - p.col(i)))) return false;
  }
  for (const Eigen::Vector3d& edge : edges)
    for (int a = 0; a < 3; ++a)
      if (separates(edge.cross(Eigen::Vector3d::Unit(a)))) return false;
  return true;
}

// The fine tetrahedra as cells of level 0, each with the level-1 cubes it overlaps.
LevelCells fine_cells(const geometry::TetMesh& fine, const CubeGrid& grid) {
  LevelCells cells;
  cells.dofs.reserve(4 * static_cast<std::size_t>(fine.tet_count()));
  for (int t = 0; t < fine.tet_count(); ++t) {
    for (int a = 0; a < 4; ++a) cells.dofs.push_back(fine.tets(t, a));
    cells.dof_offsets.push_back(static_cast<int>(cells.dofs.size()));
    const Eigen::Matrix<double, 3, 4> c = fine.corners(t);
    const Eigen::Vector3i lo = grid.cube_of(c.rowwise().minCoeff());
    const Eigen::Vector3i hi = grid.cube_of(c.rowwise().maxCoeff());
    for (int k = lo[2]; k <= hi[2]; ++k)
      for (int j = lo[1]; j <= hi[1]; ++j)
        for (int i = lo[0]; i <= hi[0]; ++i) {
          const Eigen::Vector3i cube(i, j, k);
          if (tet_overlaps_cube(c, grid.origin + grid.h * cube.cast<double>(), grid.h))
            cells.cubes.push_back(cube);
        }
    cells.cube_offsets.push_back(static_cast<int>(cells.cubes.size()));
  }
  return cells;
}

// Cells over the split DOFs: each original DOF replaced by all of its parts.
LevelCells split_cells(const LevelCells& cells, const std::vector<int>& parent) {
  std::vector<std::vector<int>> parts(
      cells.dofs.empty() ? 0 : *std::max_element(cells.dofs.begin(), cells.dofs.end()) + 1);
  for (int d = 0; d < static_cast<int>(parent.size()); ++d)
    if (parent[d] < static_cast<int>(parts.size())) parts[parent[d]].push_back(d);
  LevelCells split;
  for (int c = 0; c < cells.cell_count(); ++c) {
    for (int k = cells.dof_offsets[c]; k < cells.dof_offsets[c + 1]; ++k)
      for (const int d : parts[cells.dofs[k]]) split.dofs.push_back(d);
    split.dof_offsets.push_back(static_cast<int>(split.dofs.size()));
  }
  return split;
}

// Level-(l+1) cells seen from level l+2: each lies in the cube containing its own (halved).
void assign_parent_cubes(LevelCells& cells, const std::vector<Eigen::Vector3i>& cell_cubes) {
  cells.cubes.clear();
  cells.cube_offsets.assign(1, 0);
  for (const Eigen::Vector3i& cube : cell_cubes) {
    cells.cubes.push_back(Eigen::Vector3i(cube[0] / 2, cube[1] / 2, cube[2] / 2));
    cells.cube_offsets.push_back(static_cast<int>(cells.cubes.size()));
  }
}

// Vertex adjacency of a tetrahedral mesh (each vertex's neighbours, sorted, without itself).
std::vector<std::vector<int>> mesh_adjacency(const geometry::TetMesh& mesh) {
  std::vector<std::vector<int>> adjacency(mesh.vertex_count());
  for (int t = 0; t < mesh.tet_count(); ++t)
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b)
        if (a != b) adjacency[mesh.tets(t, a)].push_back(mesh.tets(t, b));
  for (std::vector<int>& row : adjacency) {
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
  }
  return adjacency;
}

// Splits every coarse grid vertex into one degree of freedom per connected component of its
// support (the finer-level vertices giving it a non-zero weight, connected through `adjacency`,
// the finer level's matrix graph). A coarse cube that straddles two parts of the body separated
// by a gap (a bunny's ear and its back) would otherwise tie their motions together in the coarse
// space, which the smoother cannot undo. Rewrites p's coarse indices; returns each DOF's grid
// vertex. Grid vertices without support keep one (constrained) DOF.
std::vector<int> split_by_components(Prolongation& p,
                                     const std::vector<std::vector<int>>& adjacency) {
  const int grid_vertices = p.coarse_vertex_count;
  const int n = p.fine_vertex_count();
  // Support of each grid vertex as (fine vertex, slot) pairs, CSR.
  std::vector<int> offsets(grid_vertices + 1, 0);
  for (int v = 0; v < n; ++v)
    for (int s = 0; s < 4; ++s)
      if (p.weights[v][s] != 0.0) ++offsets[p.vertices[v][s] + 1];
  for (int c = 0; c < grid_vertices; ++c) offsets[c + 1] += offsets[c];
  std::vector<int> support(offsets.back());
  std::vector<int> fill(offsets.begin(), offsets.end() - 1);
  for (int v = 0; v < n; ++v)
    for (int s = 0; s < 4; ++s)
      if (p.weights[v][s] != 0.0) support[fill[p.vertices[v][s]]++] = 4 * v + s;
  std::vector<int> slot_of(n, -1), component(n, -1), stamp(n, -1), stack;
  std::vector<int> grid_vertex_of_dof;
  std::vector<std::array<int, 4>> renumbered = p.vertices;
  for (int c = 0; c < grid_vertices; ++c) {
    if (offsets[c] == offsets[c + 1]) {
      grid_vertex_of_dof.push_back(c);
      continue;
    }
    for (int k = offsets[c]; k < offsets[c + 1]; ++k) {
      stamp[support[k] / 4] = c;
      slot_of[support[k] / 4] = support[k] % 4;
      component[support[k] / 4] = -1;
    }
    for (int k = offsets[c]; k < offsets[c + 1]; ++k) {
      const int seed = support[k] / 4;
      if (component[seed] >= 0) continue;
      const int dof = static_cast<int>(grid_vertex_of_dof.size());
      grid_vertex_of_dof.push_back(c);
      component[seed] = dof;
      stack.assign(1, seed);
      while (!stack.empty()) {
        const int v = stack.back();
        stack.pop_back();
        renumbered[v][slot_of[v]] = dof;
        for (const int u : adjacency[v])
          if (stamp[u] == c && component[u] < 0) {
            component[u] = dof;
            stack.push_back(u);
          }
      }
    }
  }
  // Zero-weight slots keep a valid index: the first DOF of their grid vertex.
  std::vector<int> first_dof(grid_vertices, -1);
  for (int d = static_cast<int>(grid_vertex_of_dof.size()) - 1; d >= 0; --d)
    first_dof[grid_vertex_of_dof[d]] = d;
  for (int v = 0; v < n; ++v)
    for (int s = 0; s < 4; ++s)
      if (p.weights[v][s] == 0.0) renumbered[v][s] = first_dof[p.vertices[v][s]];
  p.vertices = std::move(renumbered);
  p.coarse_vertex_count = static_cast<int>(grid_vertex_of_dof.size());
  return grid_vertex_of_dof;
}

// Matrix graph of the coarse level: DOFs a, b are neighbours when fine neighbours (or one fine
// vertex) i, j have w_ia != 0 and w_jb != 0 (the pattern of P^T A P).
std::vector<std::vector<int>> coarse_adjacency(const Prolongation& p,
                                               const std::vector<std::vector<int>>& fine) {
  std::vector<std::vector<int>> adjacency(p.coarse_vertex_count);
  const auto link = [&](int i, int j) {
    for (int s = 0; s < 4; ++s)
      if (p.weights[i][s] != 0.0)
        for (int t = 0; t < 4; ++t)
          if (p.weights[j][t] != 0.0 && p.vertices[i][s] != p.vertices[j][t])
            adjacency[p.vertices[i][s]].push_back(p.vertices[j][t]);
  };
  for (int i = 0; i < p.fine_vertex_count(); ++i) {
    link(i, i);
    for (const int j : fine[i]) link(i, j);
  }
  for (std::vector<int>& row : adjacency) {
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
  }
  return adjacency;
}

}  // namespace

void Prolongation::prolong_add(const Eigen::VectorXd& coarse, Eigen::VectorXd& fine) const {
  const int n = fine_vertex_count();
#pragma omp parallel for schedule(static) if (n >= 4096)
  for (int v = 0; v < n; ++v)
    for (int s = 0; s < 4; ++s)
      fine.segment<3>(3 * v) += weights[v][s] * coarse.segment<3>(3 * vertices[v][s]);
}

void Prolongation::build_transpose() {
  transpose_offsets.assign(coarse_vertex_count + 1, 0);
  for (int v = 0; v < fine_vertex_count(); ++v)
    for (int s = 0; s < 4; ++s)
      if (weights[v][s] != 0.0) ++transpose_offsets[vertices[v][s] + 1];
  for (int c = 0; c < coarse_vertex_count; ++c) transpose_offsets[c + 1] += transpose_offsets[c];
  transpose_entries.resize(transpose_offsets.back());
  std::vector<int> fill(transpose_offsets.begin(), transpose_offsets.end() - 1);
  for (int v = 0; v < fine_vertex_count(); ++v)
    for (int s = 0; s < 4; ++s)
      if (weights[v][s] != 0.0) transpose_entries[fill[vertices[v][s]]++] = {v, weights[v][s]};
}

void Prolongation::restrict_to(const Eigen::VectorXd& fine, Eigen::VectorXd& coarse) const {
  coarse.setZero(3 * coarse_vertex_count);
  if (!transpose_offsets.empty()) {
    // Gather: each coarse vertex sums its own terms (no race, same order for any thread count).
#pragma omp parallel for schedule(static) if (coarse_vertex_count >= 1024)
    for (int c = 0; c < coarse_vertex_count; ++c) {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (int k = transpose_offsets[c]; k < transpose_offsets[c + 1]; ++k)
        sum += transpose_entries[k].second * fine.segment<3>(3 * transpose_entries[k].first);
      coarse.segment<3>(3 * c) = sum;
    }
    return;
  }
  // A scatter (P is stored by fine rows); serial keeps it race-free and deterministic.
  for (int v = 0; v < fine_vertex_count(); ++v)
    for (int s = 0; s < 4; ++s)
      if (weights[v][s] != 0.0)
        coarse.segment<3>(3 * vertices[v][s]) += weights[v][s] * fine.segment<3>(3 * v);
}

Eigen::SparseMatrix<double> Prolongation::to_sparse() const {
  std::vector<Eigen::Triplet<double>> entries;
  for (int v = 0; v < fine_vertex_count(); ++v)
    for (int s = 0; s < 4; ++s)
      if (weights[v][s] != 0.0)
        for (int c = 0; c < 3; ++c)
          entries.emplace_back(3 * v + c, 3 * vertices[v][s] + c, weights[v][s]);
  Eigen::SparseMatrix<double> p(3 * fine_vertex_count(), 3 * coarse_vertex_count);
  p.setFromTriplets(entries.begin(), entries.end());
  return p;
}

double mean_edge_length(const geometry::TetMesh& mesh) {
  double sum = 0.0;
  for (int t = 0; t < mesh.tet_count(); ++t) {
    const Eigen::Matrix<double, 3, 4> c = mesh.corners(t);
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) sum += (c.col(a) - c.col(b)).norm();
  }
  return mesh.tet_count() > 0 ? sum / (6.0 * mesh.tet_count()) : 0.0;
}

TetHierarchy::TetHierarchy(const geometry::TetMesh& fine, const std::vector<char>& constrained,
                           const TetHierarchySettings& settings) {
  if (fine.tet_count() == 0) fail_hierarchy("empty mesh");
  if (!constrained.empty() && static_cast<int>(constrained.size()) != fine.vertex_count())
    fail_hierarchy("constraint vector has " + std::to_string(constrained.size()) + " entries for " +
                   std::to_string(fine.vertex_count()) + " vertices");
  if (settings.first_cell_factor <= 0.0 || settings.max_coarsest_vertices < 1 ||
      settings.max_levels < 1)
    fail_hierarchy("invalid settings");
  m_constrained.push_back(constrained.empty() ? std::vector<char>(fine.vertex_count(), 0)
                                              : constrained);
  Eigen::AlignedBox3d box(fine.vertices.colwise().minCoeff().transpose(),
                          fine.vertices.colwise().maxCoeff().transpose());
  const CubeGrid grid = cube_grid(box, settings.first_cell_factor * mean_edge_length(fine));
  m_positions.push_back(fine.vertices);
  std::vector<std::vector<int>> adjacency = mesh_adjacency(fine);
  LevelCells cells = fine_cells(fine, grid);
  std::vector<Eigen::Vector3i> points;  // grid points of the current coarse level's DOFs
  // Level 0 works in coordinates; coarser levels on integer grid points (exact).
  const LocalCoordinates fine_local = [&](int v, const Eigen::Vector3i& cube) {
    return Eigen::Vector3d((fine.vertices.row(v).transpose() - grid.origin) / grid.h -
                           cube.cast<double>());
  };
  const HomeCube fine_home = [&](int v) { return grid.cube_of(fine.vertices.row(v).transpose()); };
  const LocalCoordinates coarse_local = [&](int v, const Eigen::Vector3i& cube) {
    return Eigen::Vector3d(0.5 * (points[v] - 2 * cube).cast<double>());
  };
  const HomeCube coarse_home = [&](int v) {
    return Eigen::Vector3i(points[v][0] / 2, points[v][1] / 2, points[v][2] / 2);
  };
  double h = grid.h;
  while (vertex_count(level_count() - 1) > settings.max_coarsest_vertices &&
         level_count() < settings.max_levels) {
    const bool first = level_count() == 1;
    CompositeLevel coarse =
        composite_coarsening(cells, vertex_count(level_count() - 1), m_constrained.back(),
                             first ? fine_local : coarse_local, first ? fine_home : coarse_home);
    Prolongation& p = coarse.prolongation;
    const std::vector<int> parent = split_by_components(p, adjacency);
    if (p.coarse_vertex_count > 0.75 * vertex_count(level_count() - 1)) break;
    // Coarse vertices with no free fine vertex in their support are constrained.
    std::vector<char> coarse_constrained(p.coarse_vertex_count, 1);
    for (int v = 0; v < p.fine_vertex_count(); ++v)
      for (int s = 0; s < 4; ++s)
        if (p.weights[v][s] != 0.0) coarse_constrained[p.vertices[v][s]] = 0;
    Eigen::MatrixX3d positions(p.coarse_vertex_count, 3);
    for (int d = 0; d < p.coarse_vertex_count; ++d)
      positions.row(d) = (grid.origin + h * coarse.points[parent[d]].cast<double>()).transpose();
    adjacency = coarse_adjacency(p, adjacency);
    std::vector<Eigen::Vector3i> sorted = coarse.points;
    std::sort(sorted.begin(), sorted.end(), [](const Eigen::Vector3i& a, const Eigen::Vector3i& b) {
      return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
    });
    m_grid_point_counts.push_back(
        static_cast<int>(std::unique(sorted.begin(), sorted.end()) - sorted.begin()));
    p.build_transpose();
    m_prolongations.push_back(std::move(p));
    m_constrained.push_back(std::move(coarse_constrained));
    m_positions.push_back(std::move(positions));
    m_cell_sizes.push_back(h);
    points.resize(parent.size());
    for (std::size_t d = 0; d < parent.size(); ++d) points[d] = coarse.points[parent[d]];
    cells = split_cells(coarse.cells, parent);
    assign_parent_cubes(cells, coarse.cell_cubes);
    h *= 2.0;
  }
}

}  // namespace mgelastic::tet
