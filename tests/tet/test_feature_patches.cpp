// Block solves on patches around low-valence vertices (feature_patches.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "mgelastic/core/error.hpp"
#include "mgelastic/tet/corotated_assembly.hpp"
#include "mgelastic/tet/feature_patches.hpp"
#include "tet/step_matrix_test_support.hpp"
#include "tet/tet_test_support.hpp"

namespace mgelastic::tet {
namespace {

// A dense 3n x 3n solve of an SPD step matrix: round-off relative to |b|.
constexpr double kSolveRoundoff = 1e-10;

std::vector<int> valences(const geometry::TetMesh& mesh) {
  std::vector<int> valence(mesh.vertex_count(), 0);
  for (int t = 0; t < mesh.tet_count(); ++t)
    for (int a = 0; a < 4; ++a) ++valence[mesh.tets(t, a)];
  return valence;
}

TEST(FeaturePatches, SeedsAreFreeLowValenceVerticesWithBoundedFreePatches) {
  const geometry::TetMesh mesh = test::box_mesh(Eigen::Vector3d(1.0, 0.25, 0.25), 1.0 / 16);
  std::vector<char> fixed(mesh.vertex_count(), 0);
  for (int v = 0; v < mesh.vertex_count(); ++v) fixed[v] = mesh.vertices(v, 0) < 1e-9;
  const BlockRowMatrix<double> a = test::stiff_step_matrix(mesh);
  const FeaturePatches patches(mesh, fixed, a, {3, 5});
  const std::vector<int> valence = valences(mesh);
  int seeds = 0;
  for (int v = 0; v < mesh.vertex_count(); ++v) seeds += valence[v] <= 3 && fixed[v] == 0;
  ASSERT_GT(seeds, 0);
  EXPECT_EQ(patches.patch_count(), seeds);
  for (int p = 0; p < patches.patch_count(); ++p) {
    const std::vector<int>& patch = patches.patch(p);
    EXPECT_LE(valence[patch[0]], 3);
    EXPECT_LE(patch.size(), 5U);
    EXPECT_GT(patch.size(), 1U);
    for (const int v : patch) EXPECT_EQ(fixed[v], 0) << "patch " << p;
  }
  EXPECT_EQ(FeaturePatches(mesh, fixed, a, {0, 5}).patch_count(), 0);
}

// A patch holding every vertex is the exact solve: one pass from zero leaves round-off.
TEST(FeaturePatches, APatchCoveringTheMeshSolvesExactly) {
  const geometry::TetMesh mesh = test::box_mesh(Eigen::Vector3d(1.0, 0.25, 0.25), 0.25);
  const std::vector<char> free(mesh.vertex_count(), 0);
  BlockRowMatrix<double> a = test::stiff_step_matrix(mesh);
  FeaturePatches patches(mesh, free, a, {1000, mesh.vertex_count()});
  ASSERT_GT(patches.patch_count(), 0);
  ASSERT_EQ(static_cast<int>(patches.patch(0).size()), mesh.vertex_count());
  patches.factor(a);
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> uniform(-1, 1);
  Eigen::VectorXd b(3 * mesh.vertex_count()), x = Eigen::VectorXd::Zero(b.size()), ax;
  for (int i = 0; i < b.size(); ++i) b[i] = uniform(rng);
  patches.pass(a, b, x, true);
  a.multiply(x, ax);
  EXPECT_LE((b - ax).norm(), kSolveRoundoff * b.norm());
}

TEST(FeaturePatches, RejectsAnEmptyPatchSize) {
  const geometry::TetMesh mesh = test::box_mesh(Eigen::Vector3d(1.0, 0.25, 0.25), 0.25);
  EXPECT_THROW(FeaturePatches(mesh, std::vector<char>(mesh.vertex_count(), 0),
                              test::stiff_step_matrix(mesh), {3, 0}),
               Error);
}

}  // namespace
}  // namespace mgelastic::tet

namespace mgelastic::tet {
namespace {

// Externally chosen patches (patch_seeds.hpp) are kept as given and checked.
TEST(FeaturePatches, ExplicitPatchesAreKeptAndValidated) {
  std::vector<char> fixed(10, 0);
  fixed[9] = 1;
  const FeaturePatches patches({{2, 3, 4}, {7}}, fixed);
  ASSERT_EQ(patches.patch_count(), 2);
  EXPECT_EQ(patches.patch(0), (std::vector<int>{2, 3, 4}));
  EXPECT_EQ(patches.patch(1), (std::vector<int>{7}));
  EXPECT_THROW(FeaturePatches({{}}, fixed), Error);
  EXPECT_THROW(FeaturePatches({{1, 10}}, fixed), Error);
  EXPECT_THROW(FeaturePatches({{1, 9}}, fixed), Error);
  EXPECT_THROW(FeaturePatches({{1, 2, 1}}, fixed), Error);
  FeaturePatches appended = patches;
  appended.append(FeaturePatches({{5, 6}}, fixed));
  ASSERT_EQ(appended.patch_count(), 3);
  EXPECT_EQ(appended.patch(2), (std::vector<int>{5, 6}));
}

}  // namespace
}  // namespace mgelastic::tet
