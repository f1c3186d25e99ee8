#include "mgelastic/tet/tet_hierarchy.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_map>

#include "mgelastic/core/error.hpp"
#include "mgelastic/geometry/tet_mesh_grid.hpp"

namespace mgelastic::tet {
namespace {

[[noreturn]] void fail(const std::string& reason) {
  throw Error(reason, ErrorContext{std::string(), -1, "TetHierarchy"});
}

// Weights below this (relative to 1) are round-off of a vertex lying on a face/edge/corner.
constexpr double kZeroWeight = 1e-12;

// Cube grid shared by regular_tet_grid and the occupancy predicate.
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

// Regular grid of cube size h whose cubes overlap the bounding box of some fine tetrahedron.
geometry::RegularTetGrid covering_grid(const geometry::TetMesh& fine,
                                       const Eigen::AlignedBox3d& box, double h) {
  const CubeGrid grid = cube_grid(box, h);
  const long long total = static_cast<long long>(grid.cells[0]) * grid.cells[1] * grid.cells[2];
  if (total > (1LL << 31)) fail("coarse grid too large (cube size " + std::to_string(h) + ")");
  std::vector<char> occupied(static_cast<std::size_t>(total), 0);
  for (int t = 0; t < fine.tet_count(); ++t) {
    const Eigen::Matrix<double, 3, 4> c = fine.corners(t);
    const Eigen::Vector3i lo = grid.cube_of(c.rowwise().minCoeff());
    // A box ending exactly on a cube face does not reach into the next cube (Kuhn grids).
    const Eigen::Vector3i hi = grid.cube_of(c.rowwise().maxCoeff().array() - 1e-9 * h);
    for (int k = lo[2]; k <= hi[2]; ++k)
      for (int j = lo[1]; j <= hi[1]; ++j)
        for (int i = lo[0]; i <= hi[0]; ++i) occupied[grid.key({i, j, k})] = 1;
  }
  // Evaluated at cube centres (CENTER), where cube_of is exact.
  const auto inside = [&](const Eigen::Vector3d& p) {
    return occupied[grid.key(grid.cube_of(p))] != 0;
  };
  return geometry::regular_tet_grid(inside, box, h, geometry::CubeSelection::CENTER);
}

// Barycentric coordinates of p in tetrahedron t of `mesh`.
Eigen::Vector4d barycentric(const geometry::TetMesh& mesh, int t, const Eigen::Vector3d& p) {
  const Eigen::Matrix<double, 3, 4> c = mesh.corners(t);
  Eigen::Matrix3d edges;
  edges << c.col(1) - c.col(0), c.col(2) - c.col(0), c.col(3) - c.col(0);
  const Eigen::Vector3d l = edges.partialPivLu().solve(p - c.col(0));
  return Eigen::Vector4d(1.0 - l.sum(), l[0], l[1], l[2]);
}

// Locates the vertices of the finer level in the coarse grid; Dirichlet rows zeroed.
Prolongation locate(const Eigen::MatrixX3d& points, const std::vector<char>& fine_constrained,
                    const geometry::RegularTetGrid& coarse, const CubeGrid& grid) {
  // Cube of a Kuhn tet = component-wise minimum of its corners' grid indices.
  std::unordered_map<long long, std::vector<int>> cube_tets;
  for (int t = 0; t < coarse.mesh.tet_count(); ++t) {
    Eigen::Vector3i lo = coarse.vertex_grid_index.row(coarse.mesh.tets(t, 0)).transpose();
    for (int a = 1; a < 4; ++a)
      lo = lo.cwiseMin(coarse.vertex_grid_index.row(coarse.mesh.tets(t, a)).transpose());
    cube_tets[grid.key(lo)].push_back(t);
  }
  Prolongation p;
  p.coarse_vertex_count = coarse.mesh.vertex_count();
  const int n = static_cast<int>(points.rows());
  p.vertices.resize(n);
  p.weights.resize(n);
  int uncovered = -1;  // thrown after the parallel region
#pragma omp parallel for schedule(dynamic, 256) reduction(max : uncovered)
  for (int v = 0; v < n; ++v) {
    const Eigen::Vector3d x = points.row(v).transpose();
    const Eigen::Vector3i home = grid.cube_of(x);
    // The home cube first; its neighbours only when x is outside all its tets (round-off, or a
    // point on the boundary of the kept cubes assigned to a dropped neighbour by floor).
    int best = -1;
    double best_min = -std::numeric_limits<double>::infinity();
    Eigen::Vector4d best_w = Eigen::Vector4d::Zero();
    const auto scan = [&](const Eigen::Vector3i& cube) {
      for (int a = 0; a < 3; ++a)
        if (cube[a] < 0 || cube[a] >= grid.cells[a]) return;
      const auto found = cube_tets.find(grid.key(cube));
      if (found == cube_tets.end()) return;
      for (const int t : found->second) {
        const Eigen::Vector4d w = barycentric(coarse.mesh, t, x);
        if (w.minCoeff() > best_min) {
          best_min = w.minCoeff();
          best = t;
          best_w = w;
        }
      }
    };
    scan(home);
    if (best_min < -kZeroWeight)
      for (int k = -1; k <= 1; ++k)
        for (int j = -1; j <= 1; ++j)
          for (int i = -1; i <= 1; ++i)
            if (i != 0 || j != 0 || k != 0) scan(home + Eigen::Vector3i(i, j, k));
    if (best < 0) {
      uncovered = std::max(uncovered, v);
      continue;
    }
    const bool dirichlet = !fine_constrained.empty() && fine_constrained[v] != 0;
    for (int s = 0; s < 4; ++s) {
      p.vertices[v][s] = coarse.mesh.tets(best, s);
      p.weights[v][s] = dirichlet || std::abs(best_w[s]) < kZeroWeight ? 0.0 : best_w[s];
    }
  }
  if (uncovered >= 0)
    fail("vertex " + std::to_string(uncovered) + " is not covered by the coarse grid");
  return p;
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
  if (fine.tet_count() == 0) fail("empty mesh");
  if (!constrained.empty() && static_cast<int>(constrained.size()) != fine.vertex_count())
    fail("constraint vector has " + std::to_string(constrained.size()) + " entries for " +
         std::to_string(fine.vertex_count()) + " vertices");
  if (settings.first_cell_factor <= 0.0 || settings.max_coarsest_vertices < 1 ||
      settings.max_levels < 1)
    fail("invalid settings");
  m_constrained.push_back(constrained.empty() ? std::vector<char>(fine.vertex_count(), 0)
                                              : constrained);
  Eigen::AlignedBox3d box(fine.vertices.colwise().minCoeff().transpose(),
                          fine.vertices.colwise().maxCoeff().transpose());
  double h = settings.first_cell_factor * mean_edge_length(fine);
  m_positions.push_back(fine.vertices);
  std::vector<std::vector<int>> adjacency = mesh_adjacency(fine);
  while (vertex_count(level_count() - 1) > settings.max_coarsest_vertices &&
         level_count() < settings.max_levels) {
    geometry::RegularTetGrid coarse = covering_grid(fine, box, h);
    Prolongation p = locate(m_positions.back(), m_constrained.back(), coarse, cube_grid(box, h));
    const std::vector<int> grid_vertex = split_by_components(p, adjacency);
    if (p.coarse_vertex_count > 0.75 * vertex_count(level_count() - 1)) break;
    // Coarse vertices with no free fine vertex in their support are constrained.
    std::vector<char> coarse_constrained(p.coarse_vertex_count, 1);
    for (int v = 0; v < p.fine_vertex_count(); ++v)
      for (int s = 0; s < 4; ++s)
        if (p.weights[v][s] != 0.0) coarse_constrained[p.vertices[v][s]] = 0;
    Eigen::MatrixX3d positions(p.coarse_vertex_count, 3);
    for (int d = 0; d < p.coarse_vertex_count; ++d)
      positions.row(d) = coarse.mesh.vertices.row(grid_vertex[d]);
    adjacency = coarse_adjacency(p, adjacency);
    p.build_transpose();
    m_prolongations.push_back(std::move(p));
    m_constrained.push_back(std::move(coarse_constrained));
    m_coarse_meshes.push_back(std::move(coarse.mesh));
    m_positions.push_back(std::move(positions));
    m_cell_sizes.push_back(h);
    h *= 2.0;
  }
}

}  // namespace mgelastic::tet
