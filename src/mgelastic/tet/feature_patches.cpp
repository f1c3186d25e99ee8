#include "mgelastic/tet/feature_patches.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <string>
#include <utility>

#include "mgelastic/core/error.hpp"

namespace mgelastic::tet {
namespace {

// Passes over fewer patches run serially. A patch solve is ~10x the work of a cluster update
// (12 residual rows and two 36 x 36 substitutions), so the threshold is lower than the smoother's.
constexpr int kMinParallelPatches = 256;

[[noreturn]] void fail_feature_patches(const std::string& reason) {
  throw Error(reason, ErrorContext{std::string(), -1, "FeaturePatches"});
}

// The vertex and its nearest free matrix neighbours, breadth first, at most max_size.
std::vector<int> grow_patch(int seed, const BlockRowMatrix<double>& pattern,
                            const std::vector<char>& constrained, int max_size) {
  std::vector<int> patch{seed};
  for (std::size_t head = 0; head < patch.size(); ++head)
    for (int k = pattern.row_offsets()[patch[head]]; k < pattern.row_offsets()[patch[head] + 1];
         ++k) {
      if (static_cast<int>(patch.size()) >= max_size) return patch;
      const int j = pattern.block_columns()[k];
      if (constrained[j] == 0 && std::find(patch.begin(), patch.end(), j) == patch.end())
        patch.push_back(j);
    }
  return patch;
}

// First block of block column j of a block lower triangle with m block rows (column-major by
// blocks: column j holds the blocks of rows j..m-1).
std::size_t packed_block_column(int m, int j) {
  return static_cast<std::size_t>(j) * m - static_cast<std::size_t>(j) * (j - 1) / 2;
}

using Block = Eigen::Map<const Eigen::Matrix3d>;

}  // namespace

FeaturePatches::FeaturePatches(const geometry::TetMesh& mesh, const std::vector<char>& constrained,
                               const BlockRowMatrix<double>& pattern,
                               const FeaturePatchSettings& settings) {
  if (settings.max_size < 1) fail_feature_patches("max_size must be >= 1");
  if (pattern.block_rows() != mesh.vertex_count() ||
      static_cast<int>(constrained.size()) != mesh.vertex_count())
    fail_feature_patches("pattern or constraints do not match the mesh's " +
                         std::to_string(mesh.vertex_count()) + " vertices");
  if (settings.max_valence <= 0) return;
  // Selection: a patch around every free vertex in <= max_valence tets.
  std::vector<int> valence(mesh.vertex_count(), 0);
  for (int t = 0; t < mesh.tet_count(); ++t)
    for (int a = 0; a < 4; ++a) ++valence[mesh.tets(t, a)];
  std::vector<std::vector<int>> patches;
  for (int v = 0; v < mesh.vertex_count(); ++v)
    if (valence[v] <= settings.max_valence && constrained[v] == 0)
      patches.push_back(grow_patch(v, pattern, constrained, settings.max_size));
  build(patches, pattern);
}

// Storage, A_PP's block indices, factor offsets and colours of `patches`.
void FeaturePatches::build(const std::vector<std::vector<int>>& list,
                           const BlockRowMatrix<double>& pattern) {
  const int vertex_count = pattern.block_rows();
  m_max_size = 0;
  m_vertex_offsets.assign(1, 0);
  m_vertices.clear();
  m_block_offsets.assign(1, 0);
  m_blocks.clear();
  m_block_rows.clear();
  m_block_columns.clear();
  m_factor_offsets.assign(1, 0);
  for (const std::vector<int>& patch : list) {
    m_vertices.insert(m_vertices.end(), patch.begin(), patch.end());
    m_vertex_offsets.push_back(static_cast<int>(m_vertices.size()));
    m_max_size = std::max(m_max_size, static_cast<int>(patch.size()));
  }
  const int patches = patch_count();

  // Blocks of each A_PP on or below its diagonal, and the packed factor offsets.
  std::vector<int> local(vertex_count, -1);
  for (int p = 0; p < patches; ++p) {
    const int first = m_vertex_offsets[p], m = m_vertex_offsets[p + 1] - first;
    for (int r = 0; r < m; ++r) local[m_vertices[first + r]] = r;
    for (int r = 0; r < m; ++r) {
      const int i = m_vertices[first + r];
      for (int k = pattern.row_offsets()[i]; k < pattern.row_offsets()[i + 1]; ++k) {
        const int c = local[pattern.block_columns()[k]];
        if (c < 0 || c > r) continue;
        m_blocks.push_back(k);
        m_block_rows.push_back(r);
        m_block_columns.push_back(c);
      }
    }
    for (int r = 0; r < m; ++r) local[m_vertices[first + r]] = -1;
    m_block_offsets.push_back(static_cast<int>(m_blocks.size()));
    m_factor_offsets.push_back(m_factor_offsets.back() + 9 * packed_block_column(m, m));
  }
  m_factors.assign(m_factor_offsets.back(), 0.0);

  // Greedy colouring in patch order: a patch takes the first colour not used by a patch that
  // holds one of its vertices or their matrix neighbours.
  std::vector<int> holder_offsets(vertex_count + 1, 0), holders(m_vertices.size());
  for (const int v : m_vertices) ++holder_offsets[v + 1];
  for (int v = 0; v < vertex_count; ++v) holder_offsets[v + 1] += holder_offsets[v];
  {
    std::vector<int> fill(holder_offsets.begin(), holder_offsets.end() - 1);
    for (int p = 0; p < patches; ++p)
      for (int q = m_vertex_offsets[p]; q < m_vertex_offsets[p + 1]; ++q)
        holders[fill[m_vertices[q]]++] = p;
  }
  std::vector<int> color(patches, -1), seen;
  int colors = 0;
  for (int p = 0; p < patches; ++p) {
    seen.assign(colors + 1, 0);
    for (int q = m_vertex_offsets[p]; q < m_vertex_offsets[p + 1]; ++q)
      for (int k = pattern.row_offsets()[m_vertices[q]];
           k < pattern.row_offsets()[m_vertices[q] + 1]; ++k) {
        const int j = pattern.block_columns()[k];
        for (int h = holder_offsets[j]; h < holder_offsets[j + 1]; ++h)
          if (color[holders[h]] >= 0) seen[color[holders[h]]] = 1;
      }
    color[p] = static_cast<int>(std::find(seen.begin(), seen.end(), 0) - seen.begin());
    colors = std::max(colors, color[p] + 1);
  }
  m_color_offsets.assign(colors + 1, 0);
  for (int p = 0; p < patches; ++p) ++m_color_offsets[color[p] + 1];
  for (int k = 0; k < colors; ++k) m_color_offsets[k + 1] += m_color_offsets[k];
  m_order.resize(patches);
  std::vector<int> fill(m_color_offsets.begin(), m_color_offsets.end() - 1);
  for (int p = 0; p < patches; ++p) m_order[fill[color[p]]++] = p;
}

std::vector<int> FeaturePatches::patch(int p) const {
  return {m_vertices.begin() + m_vertex_offsets[p], m_vertices.begin() + m_vertex_offsets[p + 1]};
}

std::vector<int> FeaturePatches::color_patches(int k) const {
  return {m_order.begin() + m_color_offsets[k], m_order.begin() + m_color_offsets[k + 1]};
}

FeaturePatches::FeaturePatches(const std::vector<std::vector<int>>& patches,
                               const std::vector<char>& constrained,
                               const BlockRowMatrix<double>& pattern) {
  const int n = static_cast<int>(constrained.size());
  if (pattern.block_rows() != n)
    fail_feature_patches("pattern and constraints differ in their vertex counts");
  for (const std::vector<int>& patch : patches) {
    if (patch.empty()) fail_feature_patches("empty patch");
    for (std::size_t i = 0; i < patch.size(); ++i) {
      const int v = patch[i];
      if (v < 0 || v >= n)
        fail_feature_patches("patch vertex " + std::to_string(v) + " out of range");
      if (constrained[v] != 0)
        fail_feature_patches("patch vertex " + std::to_string(v) + " is constrained");
      if (std::find(patch.begin(), patch.begin() + static_cast<std::ptrdiff_t>(i), v) !=
          patch.begin() + static_cast<std::ptrdiff_t>(i))
        fail_feature_patches("patch vertex " + std::to_string(v) + " repeated");
    }
  }
  build(patches, pattern);
}

void FeaturePatches::append(const FeaturePatches& more, const BlockRowMatrix<double>& pattern) {
  std::vector<std::vector<int>> all;
  all.reserve(static_cast<std::size_t>(patch_count() + more.patch_count()));
  for (int p = 0; p < patch_count(); ++p) all.push_back(patch(p));
  for (int p = 0; p < more.patch_count(); ++p) all.push_back(more.patch(p));
  build(all, pattern);
}

void FeaturePatches::factor(const BlockRowMatrix<double>& a) {
  const int patches = patch_count();
  int failed = patches;  // the first patch that is not positive definite
#pragma omp parallel if (patches >= kMinParallelPatches)
  {
    Eigen::MatrixXd dense;  // per thread: A_PP's lower blocks, then L in place
#pragma omp for schedule(dynamic, 32) reduction(min : failed)
    for (int p = 0; p < patches; ++p) {
      const int n = 3 * (m_vertex_offsets[p + 1] - m_vertex_offsets[p]);
      dense.setZero(n, n);  // blocks of vertices not sharing a tet stay zero
      for (int e = m_block_offsets[p]; e < m_block_offsets[p + 1]; ++e)
        dense.block<3, 3>(3 * m_block_rows[e], 3 * m_block_columns[e]) = a.block(m_blocks[e]);
      Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> llt(dense);  // reads and overwrites the lower part
      if (llt.info() != Eigen::Success) {
        failed = std::min(failed, p);
        continue;
      }
      // 3x3 blocks of L; the diagonal ones inverted (lower triangular), so that both
      // substitutions are fixed-size 3x3 products.
      double* packed = m_factors.data() + m_factor_offsets[p];
      for (int j = 0; j < n / 3; ++j)
        for (int i = j; i < n / 3; ++i, packed += 9) {
          Eigen::Map<Eigen::Matrix3d> block(packed);
          if (i == j) {
            block = Eigen::Matrix3d(dense.block<3, 3>(3 * j, 3 * j).triangularView<Eigen::Lower>())
                        .triangularView<Eigen::Lower>()
                        .solve(Eigen::Matrix3d::Identity());
          } else {
            block = dense.block<3, 3>(3 * i, 3 * j);
          }
        }
    }
  }
  if (failed < patches)
    fail_feature_patches("patch around vertex " +
                         std::to_string(m_vertices[m_vertex_offsets[failed]]) +
                         " is not positive definite");
}

void FeaturePatches::solve_patch(int p, const BlockRowMatrix<double>& a, const Eigen::VectorXd& b,
                                 Eigen::VectorXd& x, double* r) const {
  const int first = m_vertex_offsets[p], m = m_vertex_offsets[p + 1] - first;
  // Residual rows of the patch, straight from the matrix blocks.
  for (int v = 0; v < m; ++v) {
    const int i = m_vertices[first + v];
    Eigen::Vector3d ri = b.segment<3>(3 * i);
    for (int k = a.row_offsets()[i]; k < a.row_offsets()[i + 1]; ++k)
      ri.noalias() -= a.block(k) * x.segment<3>(3 * a.block_columns()[k]);
    Eigen::Map<Eigen::Vector3d>(r + 3 * v) = ri;
  }
  // L y = r by block columns (y_J = L_JJ^{-1} r_J, then r_I -= L_IJ y_J below it), then
  // L^T d = y by block rows from the bottom (d_J = L_JJ^{-T} (y_J - sum_{I>J} L_IJ^T d_I)).
  const double* packed = m_factors.data() + m_factor_offsets[p];
  for (int j = 0; j < m; ++j) {
    const double* column = packed + 9 * packed_block_column(m, j);
    Eigen::Map<Eigen::Vector3d> rj(r + 3 * j);
    const Eigen::Vector3d y = Block(column) * rj;
    rj = y;
    for (int i = j + 1; i < m; ++i)
      Eigen::Map<Eigen::Vector3d>(r + 3 * i).noalias() -= Block(column + 9 * (i - j)) * y;
  }
  for (int j = m - 1; j >= 0; --j) {
    const double* column = packed + 9 * packed_block_column(m, j);
    Eigen::Map<Eigen::Vector3d> rj(r + 3 * j);
    Eigen::Vector3d s = rj;
    for (int i = j + 1; i < m; ++i)
      s.noalias() -=
          Block(column + 9 * (i - j)).transpose() * Eigen::Map<const Eigen::Vector3d>(r + 3 * i);
    rj = Block(column).transpose() * s;
  }
  for (int v = 0; v < m; ++v)
    x.segment<3>(3 * m_vertices[first + v]) += Eigen::Map<const Eigen::Vector3d>(r + 3 * v);
}

void FeaturePatches::pass(const BlockRowMatrix<double>& a, const Eigen::VectorXd& b,
                          Eigen::VectorXd& x, bool forward) const {
  const int colors = color_count();
  // One parallel region per pass, a barrier after each colour (the next colour reads its x).
#pragma omp parallel if (patch_count() >= kMinParallelPatches)
  {
    std::vector<double> r(3 * static_cast<std::size_t>(m_max_size));
    for (int step = 0; step < colors; ++step) {
      const int k = forward ? step : colors - 1 - step;
#pragma omp for schedule(static)
      for (int q = m_color_offsets[k]; q < m_color_offsets[k + 1]; ++q)
        solve_patch(m_order[q], a, b, x, r.data());
    }
  }
}

}  // namespace mgelastic::tet
