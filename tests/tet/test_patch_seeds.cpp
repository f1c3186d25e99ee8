// Adaptive feature-patch seeding from the cycle's slow error (patch_seeds.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "mgelastic/core/error.hpp"
#include "mgelastic/tet/patch_seeds.hpp"
#include "tet/step_matrix_test_support.hpp"
#include "tet/tet_test_support.hpp"

namespace mgelastic::tet {
namespace {

// A power iteration on a diagonal map converges to its largest factor: 0.9 against 0.2, the
// ratio of the rest decays like (0.2 / 0.9)^c, so 12 cycles leave it near round-off.
constexpr double kContractionTolerance = 1e-6;

// |e_v| = sum of Gaussian bumps around the given points (all three components equal).
Eigen::VectorXd bumps(const geometry::TetMesh& mesh, const std::vector<Eigen::Vector3d>& centres,
                      const std::vector<double>& heights, double width) {
  Eigen::VectorXd e = Eigen::VectorXd::Zero(3 * mesh.vertex_count());
  for (int v = 0; v < mesh.vertex_count(); ++v)
    for (std::size_t c = 0; c < centres.size(); ++c) {
      const double d2 = (mesh.vertices.row(v).transpose() - centres[c]).squaredNorm();
      e.segment<3>(3 * v).array() += heights[c] * std::exp(-d2 / (width * width));
    }
  return e;
}

int nearest_vertex(const geometry::TetMesh& mesh, const Eigen::Vector3d& p) {
  int best = 0;
  for (int v = 1; v < mesh.vertex_count(); ++v)
    if ((mesh.vertices.row(v).transpose() - p).norm() <
        (mesh.vertices.row(best).transpose() - p).norm())
      best = v;
  return best;
}

TEST(PatchSeeds, SeedsAreTheErrorsLocalMaximaAboveTheThreshold) {
  const geometry::TetMesh mesh = test::box_mesh(Eigen::Vector3d(1.0, 0.25, 0.25), 1.0 / 16);
  const BlockRowMatrix<double> a = test::stiff_step_matrix(mesh);
  const int n = mesh.vertex_count();
  const Eigen::Vector3d high(0.25, 0.125, 0.125), low(0.75, 0.125, 0.125);
  const int v_high = nearest_vertex(mesh, high), v_low = nearest_vertex(mesh, low);
  // Centred on vertices, so the bump maxima are exactly there.
  const Eigen::VectorXd e =
      bumps(mesh, {mesh.vertices.row(v_high), mesh.vertices.row(v_low)}, {1.0, 0.5}, 0.08);
  const std::vector<char> none(n, 0);
  EXPECT_EQ(slow_error_seeds(e, a, none, none, 0.01, 10), (std::vector<int>{v_high, v_low}));
  // The lower bump holds 0.25 of the largest |e_v|^2: below a threshold of 0.5.
  EXPECT_EQ(slow_error_seeds(e, a, none, none, 0.5, 10), (std::vector<int>{v_high}));
  EXPECT_EQ(slow_error_seeds(e, a, none, none, 0.01, 1), (std::vector<int>{v_high}));
  std::vector<char> excluded(n, 0), fixed(n, 0);
  excluded[v_high] = 1;
  EXPECT_EQ(slow_error_seeds(e, a, none, excluded, 0.01, 10), (std::vector<int>{v_low}));
  // Constrained vertices are never seeds: with the lower bump's half of the bar fixed, only the
  // higher bump is left.
  for (int v = 0; v < n; ++v) fixed[v] = mesh.vertices(v, 0) > 0.5;
  EXPECT_EQ(slow_error_seeds(e, a, fixed, none, 0.01, 10), (std::vector<int>{v_high}));
  EXPECT_THROW(slow_error_seeds(e.head(6), a, none, none, 0.01, 10), Error);
}

// Grown along a single bump, a patch is a superlevel set: no free neighbour outside it weighs
// more than its lightest member; it starts at the seed, is connected and holds max_size free
// vertices.
TEST(PatchSeeds, PatchesGrowAlongTheError) {
  const geometry::TetMesh mesh = test::box_mesh(Eigen::Vector3d(1.0, 0.25, 0.25), 1.0 / 16);
  const BlockRowMatrix<double> a = test::stiff_step_matrix(mesh);
  const int n = mesh.vertex_count();
  const int seed = nearest_vertex(mesh, Eigen::Vector3d(0.5, 0.125, 0.125));
  // Elongated along x (wider than the ball a breadth-first patch would take).
  Eigen::VectorXd e = Eigen::VectorXd::Zero(3 * n);
  for (int v = 0; v < n; ++v) {
    const Eigen::Vector3d d = mesh.vertices.row(v) - mesh.vertices.row(seed);
    e.segment<3>(3 * v).setConstant(
        std::exp(-d[0] * d[0] / 0.04 - (d[1] * d[1] + d[2] * d[2]) / 0.001));
  }
  std::vector<char> fixed(n, 0);
  for (int v = 0; v < n; ++v) fixed[v] = mesh.vertices(v, 0) > 0.55;
  const int max_size = 20;
  const std::vector<std::vector<int>> patches = grow_along_error({seed}, e, a, fixed, max_size);
  ASSERT_EQ(patches.size(), 1U);
  const std::vector<int>& patch = patches[0];
  ASSERT_EQ(static_cast<int>(patch.size()), max_size);
  EXPECT_EQ(patch[0], seed);
  const auto weight = [&](int v) { return e.segment<3>(3 * v).squaredNorm(); };
  double lightest = weight(seed);
  std::vector<char> member(n, 0);
  for (const int v : patch) {
    EXPECT_EQ(fixed[v], 0);
    EXPECT_EQ(member[v], 0) << "repeated " << v;
    member[v] = 1;
    lightest = std::min(lightest, weight(v));
  }
  for (std::size_t i = 1; i < patch.size(); ++i) {  // each joined next to an earlier member
    bool attached = false;
    for (int k = a.row_offsets()[patch[i]]; k < a.row_offsets()[patch[i] + 1]; ++k)
      attached |= std::find(patch.begin(), patch.begin() + static_cast<std::ptrdiff_t>(i),
                            a.block_columns()[k]) != patch.begin() + static_cast<std::ptrdiff_t>(i);
    EXPECT_TRUE(attached) << patch[i];
  }
  int free_neighbours = 0;
  for (const int v : patch)
    for (int k = a.row_offsets()[v]; k < a.row_offsets()[v + 1]; ++k) {
      const int j = a.block_columns()[k];
      if (member[j] != 0 || fixed[j] != 0) continue;
      ++free_neighbours;
      EXPECT_LE(weight(j), lightest) << j;
    }
  EXPECT_GT(free_neighbours, 0);
}

TEST(PatchSeeds, SlowErrorFindsTheSlowestModeOfTheMap) {
  const int n = 50, slow_vertex = 17;
  std::vector<char> fixed(n, 0);
  fixed[3] = 1;
  Eigen::VectorXd factor = Eigen::VectorXd::Constant(3 * n, 0.2);
  factor[3 * slow_vertex + 1] = 0.9;
  const SlowError slow = slow_error(
      n, fixed, [&](Eigen::VectorXd& v) { v = v.cwiseProduct(factor); }, 12, 1);
  EXPECT_NEAR(slow.contraction, 0.9, kContractionTolerance);
  EXPECT_NEAR(slow.e.norm(), 1.0, 1e-12);
  Eigen::Index largest = 0;
  slow.e.cwiseAbs().maxCoeff(&largest);
  EXPECT_EQ(largest, 3 * slow_vertex + 1);
  EXPECT_EQ(slow.e.segment<3>(9).norm(), 0.0);  // constrained vertex 3 starts and stays zero
}

}  // namespace
}  // namespace mgelastic::tet
