#include "mgelastic/tet/feature_patches.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <string>
#include <utility>

#include "mgelastic/core/error.hpp"

namespace mgelastic::tet {
namespace {

[[noreturn]] void fail(const std::string& reason) {
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

}  // namespace

FeaturePatches::FeaturePatches(const geometry::TetMesh& mesh, const std::vector<char>& constrained,
                               const BlockRowMatrix<double>& pattern,
                               const FeaturePatchSettings& settings) {
  if (settings.max_size < 1) fail("max_size must be >= 1");
  if (pattern.block_rows() != mesh.vertex_count() ||
      static_cast<int>(constrained.size()) != mesh.vertex_count())
    fail("pattern or constraints do not match the mesh's " + std::to_string(mesh.vertex_count()) +
         " vertices");
  if (settings.max_valence <= 0) return;
  std::vector<int> valence(mesh.vertex_count(), 0);
  for (int t = 0; t < mesh.tet_count(); ++t)
    for (int a = 0; a < 4; ++a) ++valence[mesh.tets(t, a)];
  for (int v = 0; v < mesh.vertex_count(); ++v)
    if (valence[v] <= settings.max_valence && constrained[v] == 0)
      m_patches.push_back(grow_patch(v, pattern, constrained, settings.max_size));
}

FeaturePatches::FeaturePatches(std::vector<std::vector<int>> patches,
                               const std::vector<char>& constrained)
    : m_patches(std::move(patches)) {
  const int n = static_cast<int>(constrained.size());
  for (const std::vector<int>& patch : m_patches) {
    if (patch.empty()) fail("empty patch");
    for (std::size_t i = 0; i < patch.size(); ++i) {
      const int v = patch[i];
      if (v < 0 || v >= n) fail("patch vertex " + std::to_string(v) + " out of range");
      if (constrained[v] != 0) fail("patch vertex " + std::to_string(v) + " is constrained");
      if (std::find(patch.begin(), patch.begin() + static_cast<std::ptrdiff_t>(i), v) !=
          patch.begin() + static_cast<std::ptrdiff_t>(i))
        fail("patch vertex " + std::to_string(v) + " repeated");
    }
  }
}

void FeaturePatches::append(const FeaturePatches& more) {
  m_patches.insert(m_patches.end(), more.m_patches.begin(), more.m_patches.end());
  m_inverses.clear();
}

void FeaturePatches::factor(const BlockRowMatrix<double>& a) {
  m_inverses.resize(m_patches.size());
  for (std::size_t p = 0; p < m_patches.size(); ++p) {
    const std::vector<int>& patch = m_patches[p];
    const int m = static_cast<int>(patch.size());
    Eigen::MatrixXd block = Eigen::MatrixXd::Zero(3 * m, 3 * m);
    for (int r = 0; r < m; ++r)
      for (int k = a.row_offsets()[patch[r]]; k < a.row_offsets()[patch[r] + 1]; ++k) {
        const auto column = std::find(patch.begin(), patch.end(), a.block_columns()[k]);
        if (column != patch.end())
          block.block<3, 3>(3 * r, 3 * (column - patch.begin())) = a.block(k);
      }
    const Eigen::LLT<Eigen::MatrixXd> llt(block);
    if (llt.info() != Eigen::Success)
      fail("patch around vertex " + std::to_string(patch[0]) + " is not positive definite");
    m_inverses[p] = llt.solve(Eigen::MatrixXd::Identity(3 * m, 3 * m));
  }
}

void FeaturePatches::pass(const BlockRowMatrix<double>& a, const Eigen::VectorXd& b,
                          Eigen::VectorXd& x, bool forward) const {
  const int count = patch_count();
  Eigen::VectorXd r, d;  // reused: patches have at most max_size vertices
  for (int q = 0; q < count; ++q) {
    const int p = forward ? q : count - 1 - q;
    const std::vector<int>& patch = m_patches[p];
    r.resize(3 * static_cast<Eigen::Index>(patch.size()));
    for (std::size_t i = 0; i < patch.size(); ++i) {
      Eigen::Vector3d ri = b.segment<3>(3 * patch[i]);
      for (int k = a.row_offsets()[patch[i]]; k < a.row_offsets()[patch[i] + 1]; ++k)
        ri.noalias() -= a.block(k) * x.segment<3>(3 * a.block_columns()[k]);
      r.segment<3>(3 * static_cast<Eigen::Index>(i)) = ri;
    }
    d.noalias() = m_inverses[p] * r;
    for (std::size_t i = 0; i < patch.size(); ++i)
      x.segment<3>(3 * patch[i]) += d.segment<3>(3 * static_cast<Eigen::Index>(i));
  }
}

}  // namespace mgelastic::tet
