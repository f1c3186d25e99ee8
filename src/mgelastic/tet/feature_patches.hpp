#pragma once
// Feature patches: extra block solves on the fine level at thin features (ear and claw tips).
// There the slowest V-cycle mode is a group of ~8-15 vertices moving almost rigidly against the
// rest of the feature, connected to it inside one coarse cube: too smooth for the cluster
// smoother, not representable by linear coarse functions (docs/tet-engine.md, Convergence).
// A vertex in at most `max_valence` tetrahedra sits on such a feature (a sharp surface tip or
// edge); its patch is the vertex and its nearest matrix neighbours (breadth first, free vertices
// only), at most `max_size` vertices. A pass visits the patches in order (backward: reversed):
//   x_P += A_PP^{-1} (b - A x)_P     (multiplicative Schwarz on the patches),
// with A_PP^{-1} (dense, up to 3 max_size square) refreshed by factor() every update. A forward
// pass after a forward sweep and a backward pass before a backward sweep keep the cycle symmetric.
// Serial (the patches overlap); cost ~ patches x (3 max_size)^2 per pass.
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
  FeaturePatches(std::vector<std::vector<int>> patches, const std::vector<char>& constrained);
  // Appends the patches of `more` (factor() again before the next pass).
  void append(const FeaturePatches& more);

  int patch_count() const { return static_cast<int>(m_patches.size()); }
  const std::vector<int>& patch(int p) const { return m_patches[p]; }
  // Inverts every patch block of `a` (same pattern as at construction).
  void factor(const BlockRowMatrix<double>& a);
  void pass(const BlockRowMatrix<double>& a, const Eigen::VectorXd& b, Eigen::VectorXd& x,
            bool forward) const;

 private:
  std::vector<std::vector<int>> m_patches;
  std::vector<Eigen::MatrixXd> m_inverses;
};

}  // namespace mgelastic::tet
