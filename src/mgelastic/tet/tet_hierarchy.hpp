#pragma once
// Tetrahedral multigrid hierarchy (Georgii & Westermann 2008, Sec. 4.3; hierarchy of [GW05]):
// level 0 is the simulation mesh; levels 1..L are regular tetrahedral grids (cubes split into six
// Kuhn tetrahedra, geometry::regular_tet_grid) that cover it, each with twice the cube size of
// the previous one. Level 1 has cube size `first_cell_factor` times the fine mesh's mean edge
// length; the default 1.587 = 2 / 1.26 (1.26 = mean edge of a unit cube's Kuhn tetrahedra) makes
// the coarse edges twice the fine ones, the usual factor 2 of geometric multigrid. All coarse grids
// share the origin (the fine bounding box's minimum), so the grid points of level l+1 are grid
// points of level l and its cubes are unions of 2x2x2 level-l cubes.
//
// Coverage: a cube of level l is kept when it overlaps the bounding box of some fine tetrahedron
// (selected through the cube centre, CubeSelection::CENTER, with an occupancy predicate that is
// exact for cube centres; a corner test would keep an extra layer of cubes). Hence every vertex
// of every finer level lies in a kept cube of the next coarser level.
//
// Prolongation P_l (level l+1 -> level l): fine vertex v of level l takes the barycentric
// coordinates of the coarse tetrahedron containing it (the one of its cube with the largest
// minimum coordinate; among the tets of the 27 surrounding cubes when round-off puts it just
// outside, then extrapolated linearly, which still reproduces linear fields). Stored as four
// (coarse vertex, weight) pairs per fine vertex. Restriction R_l = P_l^T.
//
// Dirichlet rule: constrained vertices of level l are excluded from the coarse correction: their
// rows of P_l are zero (weights 0), so the Galerkin operator never sees the identity rows the
// fine system has there. A coarse vertex of level l+1 is constrained when its support (the fine
// vertices giving it a non-zero weight) contains only constrained vertices (or is empty); its
// Galerkin row and column are then zero and the coarse operator puts the identity there.
//
// Split DOFs: a coarse grid vertex whose support (the finer vertices with non-zero weight) falls
// into several parts not connected through the finer level's matrix graph (a cube straddling a
// gap between two parts of the body) becomes one DOF per part, at the same position, so the
// coarse space does not tie separate parts together. Convex bodies have no splits. Before that
// split, each coarse cube gets one copy of its corners per connected piece of the fine elements
// it overlaps (composite_coarsening.hpp); corner copies no fine vertex uses are dropped.
//
// Levels: coarse levels are added until one has <= `max_coarsest_vertices` vertices (or
// `max_levels` is reached, or a coarsening no longer shrinks the vertex count by 1/4).
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <utility>
#include <vector>

#include "mgelastic/geometry/tet_mesh.hpp"

namespace mgelastic::tet {

// P: fine vertex i -> sum_{s<4} weights[i][s] * coarse value of vertices[i][s] (per component).
struct Prolongation {
  int coarse_vertex_count = 0;
  std::vector<std::array<int, 4>> vertices;    // fine_vertex_count x 4, coarse vertex indices
  std::vector<std::array<double, 4>> weights;  // fine_vertex_count x 4, 0 on constrained rows

  int fine_vertex_count() const { return static_cast<int>(vertices.size()); }
  // fine (3 Nf) += P coarse (3 Nc); vectors vertex-major.
  void prolong_add(const Eigen::VectorXd& coarse, Eigen::VectorXd& fine) const;
  // coarse (3 Nc) = P^T fine (3 Nf): a gather over the transpose when build_transpose() was
  // called (parallel over coarse vertices), else a serial scatter.
  void restrict_to(const Eigen::VectorXd& fine, Eigen::VectorXd& coarse) const;
  // P^T by coarse rows (CSR): coarse vertex c gathers transpose_entries[k] = (fine vertex, weight)
  // for k in [transpose_offsets[c], transpose_offsets[c+1]).
  void build_transpose();
  std::vector<int> transpose_offsets;
  std::vector<std::pair<int, double>> transpose_entries;
  Eigen::SparseMatrix<double> to_sparse() const;  // 3 Nf x 3 Nc, for tests
};

struct TetHierarchySettings {
  double first_cell_factor = 1.587;  // level-1 cube size / mean fine edge length
  int max_coarsest_vertices = 400;
  int max_levels = 12;  // including the fine level
};

class TetHierarchy {
 public:
  // `constrained[v]` != 0 marks a Dirichlet vertex of the fine mesh (size N or empty).
  // Throws Error for an empty mesh or a constraint vector of the wrong size.
  TetHierarchy(const geometry::TetMesh& fine, const std::vector<char>& constrained,
               const TetHierarchySettings& settings = {});

  int level_count() const { return static_cast<int>(m_constrained.size()); }
  int vertex_count(int level) const { return static_cast<int>(m_constrained[level].size()); }
  // Prolongation from level + 1 to level, 0 <= level < level_count() - 1.
  const Prolongation& prolongation(int level) const { return m_prolongations[level]; }
  const std::vector<char>& constrained(int level) const { return m_constrained[level]; }
  // Distinct grid points among a coarse level's DOFs (1 <= level < level_count()); fewer than
  // vertex_count(level) where cubes hold several disconnected pieces.
  int grid_point_count(int level) const { return m_grid_point_counts[level - 1]; }
  double cell_size(int level) const { return m_cell_sizes[level - 1]; }
  // Positions of the level's degrees of freedom (N_l x 3; level 0: the mesh's vertices). A coarse
  // grid vertex split into several DOFs (one per connected part of its support) repeats.
  const Eigen::MatrixX3d& positions(int level) const { return m_positions[level]; }

 private:
  std::vector<int> m_grid_point_counts;
  std::vector<double> m_cell_sizes;
  std::vector<Eigen::MatrixX3d> m_positions;
  std::vector<Prolongation> m_prolongations;
  std::vector<std::vector<char>> m_constrained;
};

// Mean edge length over the six edges of every tetrahedron (shared edges counted per tet).
double mean_edge_length(const geometry::TetMesh& mesh);

}  // namespace mgelastic::tet
