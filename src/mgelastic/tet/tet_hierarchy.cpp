#include "mgelastic/tet/tet_hierarchy.hpp"

#include <algorithm>
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

}  // namespace

void Prolongation::prolong_add(const Eigen::VectorXd& coarse, Eigen::VectorXd& fine) const {
  const int n = fine_vertex_count();
#pragma omp parallel for if (n >= 4096)
  for (int v = 0; v < n; ++v)
    for (int s = 0; s < 4; ++s)
      fine.segment<3>(3 * v) += weights[v][s] * coarse.segment<3>(3 * vertices[v][s]);
}

void Prolongation::restrict_to(const Eigen::VectorXd& fine, Eigen::VectorXd& coarse) const {
  // A scatter (R = P^T is stored by fine rows); serial keeps it race-free and deterministic.
  coarse.setZero(3 * coarse_vertex_count);
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
  const Eigen::MatrixX3d* points = &fine.vertices;
  while (vertex_count(level_count() - 1) > settings.max_coarsest_vertices &&
         level_count() < settings.max_levels) {
    geometry::RegularTetGrid coarse = covering_grid(fine, box, h);
    if (coarse.mesh.vertex_count() > 0.75 * vertex_count(level_count() - 1)) break;
    Prolongation p = locate(*points, m_constrained.back(), coarse, cube_grid(box, h));
    // Coarse vertices with no free fine vertex in their support are constrained.
    std::vector<char> coarse_constrained(coarse.mesh.vertex_count(), 1);
    for (int v = 0; v < p.fine_vertex_count(); ++v)
      for (int s = 0; s < 4; ++s)
        if (p.weights[v][s] != 0.0) coarse_constrained[p.vertices[v][s]] = 0;
    m_prolongations.push_back(std::move(p));
    m_constrained.push_back(std::move(coarse_constrained));
    m_coarse_meshes.push_back(std::move(coarse.mesh));
    m_cell_sizes.push_back(h);
    points = &m_coarse_meshes.back().vertices;
    h *= 2.0;
  }
}

}  // namespace mgelastic::tet
