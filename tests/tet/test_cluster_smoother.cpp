// Multicolour cluster block Gauss-Seidel (cluster_smoother.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "mgelastic/core/error.hpp"
#include "mgelastic/core/threads.hpp"
#include "mgelastic/tet/cluster_smoother.hpp"
#include "mgelastic/tet/corotated_assembly.hpp"
#include "tet/step_matrix_test_support.hpp"
#include "tet/tet_test_support.hpp"

namespace mgelastic::tet {
namespace {

// Step matrix M + h^2 K of a box (stiff enough that h^2 K dominates M).
BlockRowMatrix<double> box_step_matrix(double h) {
  return test::stiff_step_matrix(test::box_mesh(Eigen::Vector3d(1.0, 0.5, 0.5), h));
}

Eigen::VectorXd random_vector(int size, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-1, 1);
  Eigen::VectorXd v(size);
  for (int i = 0; i < size; ++i) v[i] = uniform(rng);
  return v;
}

double energy_norm(const BlockRowMatrix<double>& a, const Eigen::VectorXd& e) {
  Eigen::VectorXd ae;
  a.multiply(e, ae);
  return std::sqrt(e.dot(ae));
}

// Vertices 0 and 1 coupled with s = 3/4 (a sliver's pair), vertex 2 on its own.
TEST(ClusterSmoother, StronglyCoupledPairIsSolvedTogether) {
  BlockRowMatrix<double> a({0, 2, 4, 5}, {0, 1, 0, 1, 2});
  a.block(0) = 4.0 * Eigen::Matrix3d::Identity();
  a.block(1) = -3.0 * Eigen::Matrix3d::Identity();
  a.block(2) = -3.0 * Eigen::Matrix3d::Identity();
  a.block(3) = 4.0 * Eigen::Matrix3d::Identity();
  a.block(4) = 2.0 * Eigen::Matrix3d::Identity();
  ClusterSmoother smoother;
  smoother.build(a, {});
  smoother.factor(a, 0);
  EXPECT_EQ(smoother.cluster_count(), 2);
  EXPECT_EQ(smoother.largest_cluster(), 2);
  EXPECT_EQ(smoother.vertex_clusters()[0], smoother.vertex_clusters()[1]);
  // One sweep solves the system exactly (point Gauss-Seidel would contract by only (3/4)^2).
  const Eigen::VectorXd b = random_vector(9, 1);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(9), r;
  smoother.sweep(a, b, x, true, 1.0);
  a.multiply(x, r);
  EXPECT_LE((b - r).norm(), 1e-14 * b.norm());
  // With merging disabled the pair stays apart and one sweep does not solve it.
  ClusterSmoother points;
  points.build(a, {2.0, 4});
  points.factor(a, 0);
  EXPECT_EQ(points.cluster_count(), 3);
  x.setZero();
  points.sweep(a, b, x, true, 1.0);
  a.multiply(x, r);
  EXPECT_GT((b - r).norm(), 0.1 * b.norm());
}

TEST(ClusterSmoother, RejectsClustersLargerThanFourVertices) {
  const BlockRowMatrix<double> a = box_step_matrix(0.25);
  ClusterSmoother smoother;
  EXPECT_THROW(smoother.build(a, {0.3, 5}), Error);
  EXPECT_THROW(smoother.build(a, {0.3, 0}), Error);
}

TEST(ClusterSmoother, ClustersOfOneColourShareNoBlock) {
  const BlockRowMatrix<double> a = box_step_matrix(0.125);
  ClusterSmoother smoother;
  smoother.build(a, {});
  EXPECT_GT(smoother.clustered_vertices(), 0);
  EXPECT_LE(smoother.largest_cluster(), 4);
  const std::vector<int> cluster = smoother.vertex_clusters(), color = smoother.vertex_colors();
  int conflicts = 0;
  for (int i = 0; i < a.block_rows(); ++i)
    for (int k = a.row_offsets()[i]; k < a.row_offsets()[i + 1]; ++k) {
      const int j = a.block_columns()[k];
      if (cluster[i] != cluster[j] && color[i] == color[j]) ++conflicts;
    }
  EXPECT_EQ(conflicts, 0);
}

TEST(ClusterSmoother, ForwardThenBackwardIsSymmetricAndReducesTheEnergyError) {
  const BlockRowMatrix<double> a = box_step_matrix(0.125);
  ClusterSmoother smoother;
  smoother.build(a, {});
  smoother.factor(a, 0);
  const int n = 3 * a.block_rows();
  const auto symmetric_step = [&](const Eigen::VectorXd& b) {
    Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
    smoother.sweep(a, b, x, true, 1.0);
    smoother.sweep(a, b, x, false, 1.0);
    return x;
  };
  const Eigen::VectorXd u = random_vector(n, 2), v = random_vector(n, 3);
  EXPECT_NEAR(u.dot(symmetric_step(v)), v.dot(symmetric_step(u)),
              1e-12 * u.norm() * symmetric_step(v).norm());
  // Gauss-Seidel on an SPD matrix: the error's energy norm drops with every sweep.
  Eigen::VectorXd e = random_vector(n, 4);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
  for (int s = 0; s < 6; ++s) {
    const double before = energy_norm(a, e);
    smoother.sweep(a, zero, e, s % 2 == 0, 1.0);
    EXPECT_LT(energy_norm(a, e), before);
  }
}

TEST(ClusterSmoother, ResultDoesNotDependOnTheThreadCount) {
  const BlockRowMatrix<double> a = box_step_matrix(1.0 / 32.0);
  ClusterSmoother smoother;
  smoother.build(a, {});
  ASSERT_GT(smoother.cluster_count(), 4096);  // above the size from which sweeps go parallel
  smoother.factor(a, 0);
  const Eigen::VectorXd b = random_vector(3 * a.block_rows(), 5);
  Eigen::VectorXd one = Eigen::VectorXd::Zero(b.size()), two = one;
  const int threads = thread_count();
  set_thread_count(1);
  smoother.sweep(a, b, one, true, 1.0);
  set_thread_count(2);
  smoother.sweep(a, b, two, true, 1.0);
  set_thread_count(threads);
  EXPECT_EQ((one - two).cwiseAbs().maxCoeff(), 0.0);
}

}  // namespace
}  // namespace mgelastic::tet
