// Galerkin products P^T K P on BRC matrices: naive (Eq. 9) and stream (Algorithm 1).
#include <gtest/gtest.h>

#include <iostream>
#include <random>

#include "mgelastic/tet/corotated_assembly.hpp"
#include "mgelastic/tet/galerkin_product.hpp"
#include "mgelastic/tet/tet_hierarchy.hpp"
#include "tet/tet_test_support.hpp"

namespace mgelastic::tet {
namespace {

// Stream and naive sum the same terms in different orders: a few ulps per term relative to the
// largest term; 1e-12 of the matrix norm leaves margin for ~16 x 40 terms per block.
constexpr double kSummationOrder = 1e-12;

// Random symmetric values on the tet pattern, diagonally dominant (SPD-structured).
BlockRowMatrix<double> random_symmetric(const geometry::TetMesh& mesh, std::mt19937& rng) {
  BlockRowMatrix<double> k = tet_block_pattern<double>(mesh.tets, mesh.vertex_count());
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  for (int i = 0; i < k.block_rows(); ++i)
    for (int b = k.row_offsets()[i]; b < k.row_offsets()[i + 1]; ++b) {
      const int j = k.block_columns()[b];
      if (j < i) continue;
      Eigen::Matrix3d m;
      for (int e = 0; e < 9; ++e) m(e / 3, e % 3) = value(rng);
      if (j == i) m = m * m.transpose() + 40.0 * Eigen::Matrix3d::Identity();
      k.block(b) = m;
      k.block(k.find(j, i)) = m.transpose();
    }
  return k;
}

// A random prolongation: four distinct coarse vertices with random weights, some rows zero.
Prolongation random_prolongation(int fine, int coarse, std::mt19937& rng) {
  Prolongation p;
  p.coarse_vertex_count = coarse;
  std::uniform_int_distribution<int> pick(0, coarse - 1);
  std::uniform_real_distribution<double> weight(0.0, 1.0);
  for (int v = 0; v < fine; ++v) {
    std::array<int, 4> vertices{};
    for (int s = 0; s < 4; ++s) {
      do vertices[s] = pick(rng);
      while (std::find(vertices.begin(), vertices.begin() + s, vertices[s]) !=
             vertices.begin() + s);
    }
    std::array<double, 4> weights{};
    for (int s = 0; s < 4; ++s) weights[s] = v % 7 == 0 ? 0.0 : weight(rng);
    p.vertices.push_back(vertices);
    p.weights.push_back(weights);
  }
  return p;
}

double max_difference(const BlockRowMatrix<double>& a, const BlockRowMatrix<double>& b) {
  double difference = 0.0;
  for (int k = 0; k < a.block_count(); ++k)
    difference = std::max(difference, (a.block(k) - b.block(k)).cwiseAbs().maxCoeff());
  return difference;
}

double max_entry(const BlockRowMatrix<double>& a) {
  double m = 0.0;
  for (int k = 0; k < a.block_count(); ++k) m = std::max(m, a.block(k).cwiseAbs().maxCoeff());
  return m;
}

TEST(GalerkinProduct, StreamAndNaiveEqualDenseProductOnASmallRandomCase) {
  std::mt19937 rng(3);
  const geometry::TetMesh mesh = test::box_mesh(Eigen::Vector3d(1.0, 0.5, 0.5), 0.25);
  const BlockRowMatrix<double> k = random_symmetric(mesh, rng);
  const Prolongation p = random_prolongation(k.block_rows(), 9, rng);
  BlockRowMatrix<double> naive = galerkin_pattern(k, p), streamed = naive;
  galerkin_naive(k, p, naive);
  GalerkinStream(k, p, streamed, 2).update(k, streamed);
  const Eigen::SparseMatrix<double> ps = p.to_sparse();
  const Eigen::MatrixXd dense =
      Eigen::MatrixXd(ps.transpose()) * Eigen::MatrixXd(k.to_sparse()) * Eigen::MatrixXd(ps);
  const double scale = dense.cwiseAbs().maxCoeff();
  EXPECT_LE((Eigen::MatrixXd(naive.to_sparse()) - dense).cwiseAbs().maxCoeff(),
            kSummationOrder * scale);
  EXPECT_LE((Eigen::MatrixXd(streamed.to_sparse()) - dense).cwiseAbs().maxCoeff(),
            kSummationOrder * scale);
}

TEST(GalerkinProduct, StreamEqualsNaiveOnRandomMatrices) {
  std::mt19937 rng(5);
  const geometry::TetMesh mesh = test::box_mesh(Eigen::Vector3d(1.0, 0.5, 0.5), 0.1);
  for (int trial = 0; trial < 3; ++trial) {
    const BlockRowMatrix<double> k = random_symmetric(mesh, rng);
    const Prolongation p = random_prolongation(k.block_rows(), 40 + 30 * trial, rng);
    BlockRowMatrix<double> naive = galerkin_pattern(k, p), streamed = naive;
    galerkin_naive(k, p, naive);
    const GalerkinStream stream(k, p, streamed, 1 + trial);
    stream.update(k, streamed);
    EXPECT_LE(max_difference(naive, streamed), kSummationOrder * max_entry(naive))
        << "trial " << trial;
  }
}

TEST(GalerkinProduct, StreamIsBitIdenticalForAnyStreamCount) {
  std::mt19937 rng(9);
  const geometry::TetMesh mesh = test::box_mesh(Eigen::Vector3d(1.0, 0.5, 0.5), 0.1);
  const BlockRowMatrix<double> k = random_symmetric(mesh, rng);
  const Prolongation p = random_prolongation(k.block_rows(), 60, rng);
  BlockRowMatrix<double> one = galerkin_pattern(k, p), four = one;
  GalerkinStream(k, p, one, 1).update(k, one);
  const GalerkinStream stream(k, p, four, 4);
  EXPECT_EQ(stream.stream_count(), 4);
  stream.update(k, four);
  EXPECT_EQ(max_difference(one, four), 0.0);
}

TEST(GalerkinProduct, StreamEqualsNaiveOnARealHierarchyWithRotatedStiffness) {
  std::mt19937 rng(13);
  const geometry::TetMesh mesh = test::box_mesh(Eigen::Vector3d(1.0, 0.25, 0.25), 1.0 / 24);
  const TetBody body(mesh, ElementMaterials::uniform(mesh.tet_count(), {1e5, 0.3, 1000.0}));
  // Rotations of a randomly deformed (twisted and jittered) state.
  RotationField rotations(body, RotationMethod::POLAR);
  Eigen::VectorXd x = body.rest_positions();
  std::normal_distribution<double> noise(0.0, 0.01);
  for (int v = 0; v < body.vertex_count(); ++v) {
    const Eigen::Vector3d r = x.segment<3>(3 * v);
    x.segment<3>(3 * v) = Eigen::AngleAxisd(2.0 * r[0], Eigen::Vector3d::UnitX()) * r;
    for (int a = 0; a < 3; ++a) x[3 * v + a] += noise(rng);
  }
  rotations.update(x);
  CorotatedAssembler assembler(body);
  assembler.assemble(rotations);
  std::vector<char> fixed(mesh.vertex_count(), 0);
  for (int v = 0; v < mesh.vertex_count(); ++v) fixed[v] = mesh.vertices(v, 0) < 0.05;
  TetHierarchySettings settings;
  settings.max_coarsest_vertices = 60;
  const TetHierarchy hierarchy(mesh, fixed, settings);
  ASSERT_GE(hierarchy.level_count(), 3);
  BlockRowMatrix<double> fine = assembler.stiffness();
  std::size_t bytes = 0;
  for (int l = 0; l + 1 < hierarchy.level_count(); ++l) {
    BlockRowMatrix<double> naive = galerkin_pattern(fine, hierarchy.prolongation(l)),
                           streamed = naive;
    galerkin_naive(fine, hierarchy.prolongation(l), naive);
    const GalerkinStream stream(fine, hierarchy.prolongation(l), streamed);
    stream.update(fine, streamed);
    bytes += stream.memory_bytes();
    EXPECT_LE(max_difference(naive, streamed), kSummationOrder * max_entry(naive)) << "level " << l;
    // The Galerkin operator of a symmetric matrix is symmetric.
    const Eigen::SparseMatrix<double> s = streamed.to_sparse();
    EXPECT_LE((Eigen::MatrixXd(s) - Eigen::MatrixXd(s.transpose())).cwiseAbs().maxCoeff(),
              kSummationOrder * max_entry(naive));
    fine = std::move(streamed);
  }
  std::cout << "[ stream ] " << mesh.tet_count() << " tets, " << hierarchy.level_count()
            << " levels, stream memory " << bytes << " bytes\n";
  EXPECT_GT(bytes, 0u);
}

TEST(GalerkinProduct, ControlBytesContinueBeyond127Pairs) {
  std::vector<std::uint8_t> control;
  GalerkinStream::encode_block(control, 300);
  ASSERT_EQ(control.size(), 3u);
  EXPECT_EQ(control[0], 0x80 | 127);
  EXPECT_EQ(control[1], 127);
  EXPECT_EQ(control[2], 46);
  control.clear();
  GalerkinStream::encode_block(control, 5);
  ASSERT_EQ(control.size(), 1u);
  EXPECT_EQ(control[0], 0x80 | 5);
}

}  // namespace
}  // namespace mgelastic::tet
