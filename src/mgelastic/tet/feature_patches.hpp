#pragma once
// Feature patches: extra block solves on the fine level at thin features (ear and claw tips).
// There the slowest V-cycle mode is a group of ~8-15 vertices moving almost rigidly against the
// rest of the feature, connected to it inside one coarse cube: too smooth for the cluster
// smoother, not representable by linear coarse functions (docs/tet-engine.md, Convergence).
// A vertex in at most `max_valence` tetrahedra sits on such a feature (a sharp surface tip or
// edge); its patch is the vertex and its nearest matrix neighbours (breadth first, free vertices
// only), at most `max_size` vertices. A pass is multiplicative Schwarz on the patches:
//   x_P += A_PP^{-1} (b - A x)_P     for every patch P in turn,
// with A_PP = L L^T (Cholesky, refreshed by factor() every update) solved by two block
// triangular substitutions on L's 3x3 blocks.
//
// Colours: patches P, Q get different colours when they share a vertex or a matrix block joins a
// vertex of P to one of Q (Q meets P's matrix neighbourhood). Then the solves of one colour read
// no x entry another one writes, so they run in parallel, race-free, and the result does not
// depend on the thread count. A forward pass visits the colours in order (patches of a colour in
// index order), a backward pass in reverse order: the backward pass is the adjoint of the
// forward one, so a forward pass after a forward sweep and a backward pass before a backward
// sweep keep the cycle symmetric.
//
// Storage (one contiguous array each): the vertices of patch p are
// vertices[vertex_offsets[p] .. vertex_offsets[p+1]); its factor L (m x m blocks of 3x3 for m
// vertices) is packed by block columns from factors[factor_offsets[p]]: block column J holds the
// blocks of rows J..m-1, each 9 doubles column-major, the diagonal block stored as its inverse
// L_JJ^{-1} (lower triangular). A_PP is gathered from the BRC matrix through the block indices
// recorded at construction (only blocks on or below the patch diagonal: LLT reads the lower
// triangle).
#include <Eigen/Core>
#include <vector>

#include "mgelastic/geometry/tet_mesh.hpp"
#include "mgelastic/tet/brc_matrix.hpp"

namespace mgelastic::tet {

struct FeaturePatchSettings {
  int max_valence = 0;  // patches around vertices in <= this many tets; 0 = no patches
  int max_size = 12;    // vertices per patch
};

class FeaturePatches {
 public:
  FeaturePatches() = default;
  // Throws Error for max_size < 1 or a pattern / constraint vector not matching the mesh.
  FeaturePatches(const geometry::TetMesh& mesh, const std::vector<char>& constrained,
                 const BlockRowMatrix<double>& pattern, const FeaturePatchSettings& settings);
  // Externally chosen patches (patch_seeds.hpp: grown along the cycle's slow error). Throws Error
  // for an empty patch, a vertex out of range or repeated in a patch, or a constrained vertex.
  FeaturePatches(const std::vector<std::vector<int>>& patches, const std::vector<char>& constrained,
                 const BlockRowMatrix<double>& pattern);
  // Appends the patches of `more` and colours all again (factor() before the next pass).
  void append(const FeaturePatches& more, const BlockRowMatrix<double>& pattern);

  int patch_count() const { return static_cast<int>(m_vertex_offsets.size()) - 1; }
  // The vertices of patch p (the seed first).
  std::vector<int> patch(int p) const;
  int color_count() const { return static_cast<int>(m_color_offsets.size()) - 1; }
  // The patches of colour k, in the order a forward pass visits them.
  std::vector<int> color_patches(int k) const;
  // Factors every patch block of `a` (same pattern as at construction). Throws Error when a
  // patch block is not positive definite.
  void factor(const BlockRowMatrix<double>& a);
  // One Schwarz pass over all patches, colours in order (forward) or reversed.
  void pass(const BlockRowMatrix<double>& a, const Eigen::VectorXd& b, Eigen::VectorXd& x,
            bool forward) const;
  std::size_t factor_memory_bytes() const { return m_factors.size() * sizeof(double); }

 private:
  void build(const std::vector<std::vector<int>>& patches, const BlockRowMatrix<double>& pattern);
  // x_P += A_PP^{-1} (b - A x)_P for patch p; `r` is scratch of at least 3 max_size.
  void solve_patch(int p, const BlockRowMatrix<double>& a, const Eigen::VectorXd& b,
                   Eigen::VectorXd& x, double* r) const;

  int m_max_size = 0;
  std::vector<int> m_vertex_offsets{0}, m_vertices;
  // Blocks of A_PP on or below its diagonal: for patch p the entries
  // [block_offsets[p], block_offsets[p+1]) of (matrix block index, local row, local column).
  std::vector<int> m_block_offsets{0}, m_blocks, m_block_rows, m_block_columns;
  std::vector<std::size_t> m_factor_offsets{0};
  std::vector<double> m_factors;
  std::vector<int> m_color_offsets{0}, m_order;  // patches by colour
};

}  // namespace mgelastic::tet
