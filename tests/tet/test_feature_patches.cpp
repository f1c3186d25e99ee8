// Block solves on patches around low-valence vertices (feature_patches.hpp).
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>

#include "mgelastic/core/error.hpp"
#include "mgelastic/core/threads.hpp"
#include "mgelastic/tet/corotated_assembly.hpp"
#include "mgelastic/tet/feature_patches.hpp"
#include "tet/step_matrix_test_support.hpp"
#include "tet/tet_test_support.hpp"

namespace mgelastic::tet {
namespace {

// A dense 3n x 3n solve of an SPD step matrix: round-off relative to |b|.
constexpr double kSolveRoundoff = 1e-10;

// A coloured pass against the same solves one after the other in the dense algebra: the order
// of additions differs, so round-off relative to |x|.
constexpr double kSerialRoundoff = 1e-12;
// Colouring changes the order of the Schwarz solves; the contraction may change a little.
constexpr double kColourOrderMargin = 0.05;

// Bar 1 x 0.25 x 0.25 with its left end fixed.
std::vector<char> left_end_fixed(const geometry::TetMesh& mesh) {
  std::vector<char> fixed(mesh.vertex_count(), 0);
  for (int v = 0; v < mesh.vertex_count(); ++v) fixed[v] = mesh.vertices(v, 0) < 1e-9;
  return fixed;
}

Eigen::VectorXd random_vector(Eigen::Index size, const std::vector<char>& fixed, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-1, 1);
  Eigen::VectorXd v(size);
  for (Eigen::Index i = 0; i < size; ++i) v[i] = fixed[i / 3] != 0 ? 0.0 : uniform(rng);
  return v;
}

// Multiplicative Schwarz in the dense algebra: x_P += A_PP^{-1} (b - A x)_P, patches in `order`.
void serial_schwarz(const Eigen::MatrixXd& a, const FeaturePatches& patches,
                    const std::vector<int>& order, const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  for (const int p : order) {
    const std::vector<int> patch = patches.patch(p);
    std::vector<int> rows;
    for (const int v : patch)
      for (int c = 0; c < 3; ++c) rows.push_back(3 * v + c);
    const Eigen::VectorXd r = b - a * x;
    const Eigen::MatrixXd app = a(rows, rows);
    const Eigen::VectorXd d = app.llt().solve(r(rows));
    x(rows) += d;
  }
}

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

// Patches of one colour are solved in parallel: no vertex of one may be a vertex or a matrix
// neighbour of a vertex of another. Every patch has exactly one colour.
TEST(FeaturePatches, PatchesOfOneColourShareNoVertexAndNoMatrixBlock) {
  const geometry::TetMesh mesh = test::box_mesh(Eigen::Vector3d(1.0, 0.25, 0.25), 1.0 / 8);
  const std::vector<char> fixed = left_end_fixed(mesh);
  const BlockRowMatrix<double> a = test::stiff_step_matrix(mesh);
  const FeaturePatches patches(mesh, fixed, a, {1000, 6});  // every free vertex seeds a patch
  ASSERT_GT(patches.color_count(), 1);
  std::vector<int> times_coloured(patches.patch_count(), 0);
  for (int k = 0; k < patches.color_count(); ++k) {
    const std::vector<int> members = patches.color_patches(k);
    std::vector<int> owner(mesh.vertex_count(), -1);  // patch of this colour holding the vertex
    for (const int p : members) {
      ++times_coloured[p];
      for (const int v : patches.patch(p)) {
        EXPECT_EQ(owner[v], -1) << "colour " << k << " vertex " << v;
        owner[v] = p;
      }
    }
    for (const int p : members)
      for (const int v : patches.patch(p))
        for (int e = a.row_offsets()[v]; e < a.row_offsets()[v + 1]; ++e) {
          const int j = a.block_columns()[e];
          EXPECT_TRUE(owner[j] == -1 || owner[j] == p)
              << "colour " << k << ": patches " << p << " and " << owner[j] << " coupled";
        }
  }
  for (int p = 0; p < patches.patch_count(); ++p) EXPECT_EQ(times_coloured[p], 1) << p;
}

// The parallel coloured pass is multiplicative Schwarz with the patches in colour order (the
// dense one-after-the-other solves give the same x), and that order contracts the error about as
// well as the patch (vertex) order: energy-norm contraction of a forward + backward pass.
TEST(FeaturePatches, ColouredPassIsMultiplicativeSchwarzAsGoodAsTheVertexOrder) {
  const geometry::TetMesh mesh = test::box_mesh(Eigen::Vector3d(1.0, 0.25, 0.25), 1.0 / 8);
  const std::vector<char> fixed = left_end_fixed(mesh);
  const BlockRowMatrix<double> a = test::stiff_step_matrix(mesh);
  FeaturePatches patches(mesh, fixed, a, {1000, 6});
  patches.factor(a);
  Eigen::MatrixXd dense = a.to_sparse();
  for (int v = 0; v < mesh.vertex_count(); ++v)  // Dirichlet rows and columns: the identity
    if (fixed[v] != 0) {
      dense.middleRows(3 * v, 3).setZero();
      dense.middleCols(3 * v, 3).setZero();
      dense.block<3, 3>(3 * v, 3 * v).setIdentity();
    }
  std::vector<int> colour_order, vertex_order(patches.patch_count());
  for (int k = 0; k < patches.color_count(); ++k)
    for (const int p : patches.color_patches(k)) colour_order.push_back(p);
  for (int p = 0; p < patches.patch_count(); ++p) vertex_order[p] = p;

  const Eigen::VectorXd b = random_vector(dense.rows(), fixed, 3);
  Eigen::VectorXd coloured = random_vector(dense.rows(), fixed, 4), serial = coloured;
  patches.pass(a, b, coloured, true);
  serial_schwarz(dense, patches, colour_order, b, serial);
  EXPECT_LE((coloured - serial).norm(), kSerialRoundoff * serial.norm());

  // Error e with b = 0: forward then backward pass (backward: colours reversed), 4 times.
  const auto contraction = [&](const std::vector<int>& order, bool use_pass) {
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(dense.rows());
    Eigen::VectorXd e = random_vector(dense.rows(), fixed, 5);
    const double start = std::sqrt(e.dot(dense * e));
    const std::vector<int> reversed(order.rbegin(), order.rend());
    for (int s = 0; s < 4; ++s) {
      if (use_pass) {
        patches.pass(a, zero, e, true);
        patches.pass(a, zero, e, false);
      } else {
        serial_schwarz(dense, patches, order, zero, e);
        serial_schwarz(dense, patches, reversed, zero, e);
      }
    }
    return std::pow(std::sqrt(e.dot(dense * e)) / start, 1.0 / 4);
  };
  const double by_colour = contraction(colour_order, true);
  const double by_vertex = contraction(vertex_order, false);
  std::cout << "[ schwarz ] " << patches.patch_count() << " patches, " << patches.color_count()
            << " colours: contraction per symmetric pass " << by_colour << " (vertex order "
            << by_vertex << ")\n";
  EXPECT_LT(by_colour, 1.0);
  EXPECT_LE(by_colour, by_vertex + kColourOrderMargin);
}

// The pass goes parallel from 256 patches (feature_patches.cpp); colours make it race-free, so
// 1 and 2 threads give the same bits.
TEST(FeaturePatches, PassDoesNotDependOnTheThreadCount) {
  const geometry::TetMesh mesh = test::box_mesh(Eigen::Vector3d(1.0, 0.25, 0.25), 1.0 / 16);
  const std::vector<char> fixed = left_end_fixed(mesh);
  const BlockRowMatrix<double> a = test::stiff_step_matrix(mesh);
  FeaturePatches patches(mesh, fixed, a, {1000, 12});
  ASSERT_GE(patches.patch_count(), 256);
  const int threads = thread_count();
  set_thread_count(2);
  patches.factor(a);
  const Eigen::VectorXd b = random_vector(3 * mesh.vertex_count(), fixed, 6);
  Eigen::VectorXd one = Eigen::VectorXd::Zero(b.size()), two = one;
  set_thread_count(1);
  patches.pass(a, b, one, true);
  patches.pass(a, b, one, false);
  set_thread_count(2);
  patches.pass(a, b, two, true);
  patches.pass(a, b, two, false);
  set_thread_count(threads);
  EXPECT_GT(one.norm(), 0.0);
  EXPECT_EQ((one - two).cwiseAbs().maxCoeff(), 0.0);
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
  const geometry::TetMesh mesh = test::box_mesh(Eigen::Vector3d(1.0, 0.25, 0.25), 1.0 / 4);
  const std::vector<char> fixed = left_end_fixed(mesh);
  const BlockRowMatrix<double> a = test::stiff_step_matrix(mesh);
  std::vector<int> free_vertices, fixed_vertices;
  for (int v = 0; v < mesh.vertex_count(); ++v)
    (fixed[v] != 0 ? fixed_vertices : free_vertices).push_back(v);
  ASSERT_GE(free_vertices.size(), 6u);
  ASSERT_FALSE(fixed_vertices.empty());
  const int f0 = free_vertices[0], f1 = free_vertices[1], f2 = free_vertices[2];
  const FeaturePatches patches({{f0, f1, f2}, {free_vertices[3]}}, fixed, a);
  ASSERT_EQ(patches.patch_count(), 2);
  EXPECT_EQ(patches.patch(0), (std::vector<int>{f0, f1, f2}));
  EXPECT_EQ(patches.patch(1), (std::vector<int>{free_vertices[3]}));
  EXPECT_THROW(FeaturePatches({{}}, fixed, a), Error);
  EXPECT_THROW(FeaturePatches({{f0, mesh.vertex_count()}}, fixed, a), Error);
  EXPECT_THROW(FeaturePatches({{f0, fixed_vertices[0]}}, fixed, a), Error);
  EXPECT_THROW(FeaturePatches({{f0, f1, f0}}, fixed, a), Error);
  FeaturePatches appended = patches;
  appended.append(FeaturePatches({{free_vertices[4], free_vertices[5]}}, fixed, a), a);
  ASSERT_EQ(appended.patch_count(), 3);
  EXPECT_EQ(appended.patch(2), (std::vector<int>{free_vertices[4], free_vertices[5]}));
  EXPECT_GE(appended.color_count(), 1);
}

}  // namespace
}  // namespace mgelastic::tet
