#include "mgelastic/tet/cluster_smoother.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <numeric>
#include <string>
#include <tuple>

#include "mgelastic/core/disjoint_sets.hpp"
#include "mgelastic/core/error.hpp"

namespace mgelastic::tet {
namespace {

[[noreturn]] void fail(const std::string& reason) {
  throw Error(reason, ErrorContext{std::string(), -1, "ClusterSmoother"});
}

// Levels with fewer clusters are swept serially (fork/join and barriers cost more).
constexpr int kMinParallelClusters = 4096;

// A merged cluster keeps its joint block only when it is this well conditioned.
constexpr double kMinClusterConditioning = 1e-8;

// Dense cluster blocks and vectors without heap allocation.
constexpr int kMaxClusterSize = 4;
using ClusterMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3 * kMaxClusterSize,
                                    3 * kMaxClusterSize>;
using ClusterVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 3 * kMaxClusterSize, 1>;

// Diagonal block of the vertices `members` (3|C| x 3|C|).
ClusterMatrix cluster_block(const BlockRowMatrix<double>& a, const std::vector<int>& members) {
  const int size = static_cast<int>(members.size());
  ClusterMatrix block = ClusterMatrix::Zero(3 * size, 3 * size);
  for (int p = 0; p < size; ++p)
    for (int q = 0; q < size; ++q) {
      const int k = a.find(members[p], members[q]);
      if (k >= 0) block.block<3, 3>(3 * p, 3 * q) = a.block(k);
    }
  return block;
}

// Coarse Galerkin levels can hold DOFs with the same support (dependent columns of P): their
// joint block is singular. Such clusters fall back to single vertices.
void dissolve_near_singular(const BlockRowMatrix<double>& a, std::vector<int>& parent) {
  const int n = static_cast<int>(parent.size());
  std::vector<std::vector<int>> members(n);
  for (int v = 0; v < n; ++v) members[find_root(parent, v)].push_back(v);
  for (int r = 0; r < n; ++r) {
    if (members[r].size() < 2) continue;
    const ClusterMatrix block = cluster_block(a, members[r]);
    const ClusterVector eigenvalues = Eigen::SelfAdjointEigenSolver<ClusterMatrix>(
                                          0.5 * (block + block.transpose()), Eigen::EigenvaluesOnly)
                                          .eigenvalues();
    if (eigenvalues[0] > kMinClusterConditioning * eigenvalues[eigenvalues.size() - 1]) continue;
    for (const int v : members[r]) parent[v] = v;
  }
}

}  // namespace

void ClusterSmoother::build(const BlockRowMatrix<double>& a,
                            const ClusterSmootherSettings& settings) {
  if (settings.max_cluster_size < 1 || settings.max_cluster_size > kMaxClusterSize)
    fail("max_cluster_size must be 1.." + std::to_string(kMaxClusterSize) + " (got " +
         std::to_string(settings.max_cluster_size) + ")");
  const int n = a.block_rows();
  // Strong neighbour pairs, strongest first.
  std::vector<std::tuple<double, int, int>> strong;
  for (int i = 0; i < n; ++i) {
    const double dii = a.diagonal_block(i).norm();
    for (int k = a.row_offsets()[i]; k < a.row_offsets()[i + 1]; ++k) {
      const int j = a.block_columns()[k];
      if (j <= i) continue;
      const double s = a.block(k).norm() / std::sqrt(dii * a.diagonal_block(j).norm());
      if (s > settings.strong_coupling) strong.emplace_back(s, i, j);
    }
  }
  std::sort(strong.begin(), strong.end(),
            [](const auto& x, const auto& y) { return std::get<0>(x) > std::get<0>(y); });
  std::vector<int> parent(n), size(n, 1);
  std::iota(parent.begin(), parent.end(), 0);
  for (const auto& [s, i, j] : strong) {
    const int ri = find_root(parent, i), rj = find_root(parent, j);
    if (ri == rj || size[ri] + size[rj] > settings.max_cluster_size) continue;
    parent[rj] = ri;
    size[ri] += size[rj];
  }
  dissolve_near_singular(a, parent);
  // Clusters numbered by their smallest vertex.
  std::vector<int> cluster_of(n, -1), root_cluster(n, -1);
  int clusters = 0;
  for (int v = 0; v < n; ++v) {
    const int r = find_root(parent, v);
    if (root_cluster[r] < 0) root_cluster[r] = clusters++;
    cluster_of[v] = root_cluster[r];
  }
  m_cluster_offsets.assign(clusters + 1, 0);
  for (int v = 0; v < n; ++v) ++m_cluster_offsets[cluster_of[v] + 1];
  for (int c = 0; c < clusters; ++c) m_cluster_offsets[c + 1] += m_cluster_offsets[c];
  m_vertices.assign(n, 0);
  std::vector<int> fill(m_cluster_offsets.begin(), m_cluster_offsets.end() - 1);
  for (int v = 0; v < n; ++v) m_vertices[fill[cluster_of[v]]++] = v;
  // Greedy colouring of the cluster graph (clusters adjacent when a matrix block joins them).
  std::vector<int> color(clusters, -1), seen;
  int colors = 0;
  for (int c = 0; c < clusters; ++c) {
    seen.assign(colors + 1, 0);
    for (int m = m_cluster_offsets[c]; m < m_cluster_offsets[c + 1]; ++m) {
      const int i = m_vertices[m];
      for (int k = a.row_offsets()[i]; k < a.row_offsets()[i + 1]; ++k) {
        const int other = color[cluster_of[a.block_columns()[k]]];
        if (other >= 0) seen[other] = 1;
      }
    }
    color[c] = static_cast<int>(std::find(seen.begin(), seen.end(), 0) - seen.begin());
    colors = std::max(colors, color[c] + 1);
  }
  m_color_offsets.assign(colors + 1, 0);
  for (int c = 0; c < clusters; ++c) ++m_color_offsets[color[c] + 1];
  for (int k = 0; k < colors; ++k) m_color_offsets[k + 1] += m_color_offsets[k];
  m_order.assign(clusters, 0);
  fill.assign(m_color_offsets.begin(), m_color_offsets.end() - 1);
  for (int c = 0; c < clusters; ++c) m_order[fill[color[c]]++] = c;
  m_inverse_offsets.assign(clusters + 1, 0);
  for (int c = 0; c < clusters; ++c) {
    const long long dim = 3LL * (m_cluster_offsets[c + 1] - m_cluster_offsets[c]);
    m_inverse_offsets[c + 1] = m_inverse_offsets[c] + dim * dim;
  }
  m_inverses.assign(static_cast<std::size_t>(m_inverse_offsets.back()), 0.0);
  // Blocks of each merged cluster's diagonal block (p, q), -1 when not stored; found once.
  m_block_ref_offsets.assign(clusters + 1, 0);
  m_block_refs.clear();
  for (int c = 0; c < clusters; ++c) {
    const int first = m_cluster_offsets[c], size = m_cluster_offsets[c + 1] - first;
    if (size > 1)
      for (int p = 0; p < size; ++p)
        for (int q = 0; q < size; ++q)
          m_block_refs.push_back(a.find(m_vertices[first + p], m_vertices[first + q]));
    m_block_ref_offsets[c + 1] = static_cast<int>(m_block_refs.size());
  }
}

void ClusterSmoother::factor(const BlockRowMatrix<double>& a, int level) {
  const int clusters = cluster_count();
  int failed = -1;
#pragma omp parallel for schedule(dynamic, 256) reduction(max : failed) if (clusters >= 4096)
  for (int c = 0; c < clusters; ++c) {
    const int first = m_cluster_offsets[c], size = m_cluster_offsets[c + 1] - first;
    double* out = m_inverses.data() + m_inverse_offsets[c];
    if (size == 1) {
      Eigen::Matrix3d inverse = Eigen::Matrix3d::Zero();
      bool invertible = false;
      a.diagonal_block(m_vertices[first]).computeInverseWithCheck(inverse, invertible, 1e-300);
      if (!invertible) failed = std::max(failed, c);
      Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> stored(out);
      stored = inverse;
      continue;
    }
    ClusterMatrix block = ClusterMatrix::Zero(3 * size, 3 * size);
    const int* refs = m_block_refs.data() + m_block_ref_offsets[c];
    for (int p = 0; p < size; ++p)
      for (int q = 0; q < size; ++q)
        if (const int k = refs[size * p + q]; k >= 0) block.block<3, 3>(3 * p, 3 * q) = a.block(k);
    const Eigen::LLT<ClusterMatrix> llt(block);
    if (llt.info() != Eigen::Success) {
      failed = std::max(failed, c);
      continue;
    }
    Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
        out, 3 * size, 3 * size) = llt.solve(ClusterMatrix::Identity(3 * size, 3 * size));
  }
  if (failed >= 0)
    fail("singular or indefinite diagonal block of cluster " + std::to_string(failed) +
         " (vertex " + std::to_string(m_vertices[m_cluster_offsets[failed]]) + ") on level " +
         std::to_string(level));
}

void ClusterSmoother::update_cluster(const BlockRowMatrix<double>& a, int c,
                                     const Eigen::VectorXd& b, Eigen::VectorXd& x, double w) const {
  const int first = m_cluster_offsets[c], size = m_cluster_offsets[c + 1] - first;
  const double* inverse = m_inverses.data() + m_inverse_offsets[c];
  // Residual of the cluster's rows; the cluster's own blocks are included, hence the "+=".
  ClusterVector r(3 * size);
  for (int p = 0; p < size; ++p) {
    const int i = m_vertices[first + p];
    Eigen::Vector3d ri = b.segment<3>(3 * i);
    for (int k = a.row_offsets()[i]; k < a.row_offsets()[i + 1]; ++k)
      ri.noalias() -= a.block(k) * x.segment<3>(3 * a.block_columns()[k]);
    r.segment<3>(3 * p) = ri;
  }
  if (size == 1) {
    const int i = m_vertices[first];
    x.segment<3>(3 * i) +=
        w * (Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(inverse) * r.head<3>());
    return;
  }
  const ClusterVector dx =
      Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
          inverse, 3 * size, 3 * size) *
      r;
  for (int p = 0; p < size; ++p)
    x.segment<3>(3 * m_vertices[first + p]) += w * dx.segment<3>(3 * p);
}

void ClusterSmoother::sweep(const BlockRowMatrix<double>& a, const Eigen::VectorXd& b,
                            Eigen::VectorXd& x, bool forward, double w) const {
  const int colors = color_count();
  // One parallel region per sweep, a barrier after each colour (the next colour reads its x).
#pragma omp parallel if (cluster_count() >= kMinParallelClusters)
  for (int step = 0; step < colors; ++step) {
    const int k = forward ? step : colors - 1 - step;
#pragma omp for schedule(static)
    for (int m = m_color_offsets[k]; m < m_color_offsets[k + 1]; ++m)
      update_cluster(a, m_order[m], b, x, w);
  }
}

int ClusterSmoother::largest_cluster() const {
  int largest = 0;
  for (int c = 0; c < cluster_count(); ++c)
    largest = std::max(largest, m_cluster_offsets[c + 1] - m_cluster_offsets[c]);
  return largest;
}

std::vector<int> ClusterSmoother::vertex_clusters() const {
  std::vector<int> cluster(m_vertices.size());
  for (int c = 0; c < cluster_count(); ++c)
    for (int m = m_cluster_offsets[c]; m < m_cluster_offsets[c + 1]; ++m)
      cluster[m_vertices[m]] = c;
  return cluster;
}

std::vector<int> ClusterSmoother::vertex_colors() const {
  std::vector<int> color(m_vertices.size());
  for (int k = 0; k < color_count(); ++k)
    for (int m = m_color_offsets[k]; m < m_color_offsets[k + 1]; ++m) {
      const int c = m_order[m];
      for (int v = m_cluster_offsets[c]; v < m_cluster_offsets[c + 1]; ++v)
        color[m_vertices[v]] = k;
    }
  return color;
}

int ClusterSmoother::clustered_vertices() const {
  int count = 0;
  for (int c = 0; c < cluster_count(); ++c) {
    const int size = m_cluster_offsets[c + 1] - m_cluster_offsets[c];
    if (size > 1) count += size;
  }
  return count;
}

}  // namespace mgelastic::tet
