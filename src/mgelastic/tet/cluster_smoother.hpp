#pragma once
// Multicolour cluster block Gauss-Seidel: the smoother of TetMultigrid (Georgii & Westermann 2008,
// Sec. 4.3 use Gauss-Seidel; this is its block form, ordered by colour so it runs in parallel).
//
// Clusters: vertices are grouped into clusters C (most of size 1; at most `max_cluster_size`)
// by merging strongly coupled neighbours, strongest first: i ~ j when
//   s_ij = |A_ij|_F / sqrt(|A_ii|_F |A_jj|_F) > strong_coupling.
// Why: a sliver tetrahedron couples two vertices so strongly (s ~ 1) that point-block
// Gauss-Seidel barely moves their joint motion, and the coarse grid (cubes ~5x the sliver's edge)
// cannot represent it either; on bunny.msh that one local mode set the V-cycle rate (0.68 -> see
// docs/tet-engine.md). Solving each cluster exactly removes it.
//
// Sweep (one colour after the other; forward = colours 0..c-1, backward = reversed):
//   for every cluster C of the colour, in parallel:  x_C += w A_CC^{-1} (b - A x)_C
// Clusters of one colour share no matrix block, so the updates are independent: the result does
// not depend on the thread count, and forward followed by backward is a symmetric operator.
// A_CC^{-1} is stored dense (3|C| x 3|C|, row-major, concatenated per cluster).
//
// The partition (clusters, colours) is built once from the first matrix values (strength follows
// the mesh geometry, which does not change); factor() is called on every new matrix.
#include <Eigen/Core>
#include <vector>

#include "mgelastic/tet/brc_matrix.hpp"

namespace mgelastic::tet {

struct ClusterSmootherSettings {
  double strong_coupling = 0.3;  // s_ij above which neighbours are merged; > 1 disables
  int max_cluster_size = 4;      // vertices per cluster, 1..4 (1 = point-block Gauss-Seidel)
};

class ClusterSmoother {
 public:
  ClusterSmoother() = default;
  // Clusters and colours from `a`'s values and pattern; throws Error for a max_cluster_size
  // outside 1..4.
  void build(const BlockRowMatrix<double>& a, const ClusterSmootherSettings& settings);
  // Inverse diagonal cluster blocks of `a` (same pattern as at build). Throws Error naming the
  // level and cluster when a block is not invertible.
  void factor(const BlockRowMatrix<double>& a, int level);
  // One sweep over all colours with relaxation w.
  void sweep(const BlockRowMatrix<double>& a, const Eigen::VectorXd& b, Eigen::VectorXd& x,
             bool forward, double w) const;

  int cluster_count() const { return static_cast<int>(m_cluster_offsets.size()) - 1; }
  int color_count() const { return static_cast<int>(m_color_offsets.size()) - 1; }
  int largest_cluster() const;
  // Vertices in clusters of size > 1.
  int clustered_vertices() const;
  // Per vertex: its cluster and its cluster's colour.
  std::vector<int> vertex_clusters() const;
  std::vector<int> vertex_colors() const;

 private:
  void update_cluster(const BlockRowMatrix<double>& a, int cluster, const Eigen::VectorXd& b,
                      Eigen::VectorXd& x, double w) const;

  std::vector<int> m_cluster_offsets{0};  // cluster c owns m_vertices[offsets[c] .. offsets[c+1])
  std::vector<int> m_vertices;
  std::vector<int> m_color_offsets{0};  // colour k owns m_order[offsets[k] .. offsets[k+1])
  std::vector<int> m_order;             // clusters sorted by colour
  std::vector<long long> m_inverse_offsets;
  std::vector<double> m_inverses;
  // Merged clusters: index in `a` of each 3x3 block of the cluster's diagonal block (row-major
  // over member pairs, -1 when not stored), so factor() does no search.
  std::vector<int> m_block_ref_offsets{0};
  std::vector<int> m_block_refs;
};

}  // namespace mgelastic::tet
