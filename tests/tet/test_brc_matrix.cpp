// Block-row-compressed matrix and the corotated assembly into it.
#include <gtest/gtest.h>

#include <random>

#include "mgelastic/core/error.hpp"
#include "mgelastic/core/threads.hpp"
#include "mgelastic/tet/brc_matrix.hpp"
#include "mgelastic/tet/corotated_assembly.hpp"
#include "mgelastic/tet/parallel.hpp"
#include "tet/tet_test_support.hpp"

namespace mgelastic::tet {
namespace {

using test::kMaterial;

// A small mesh deformed randomly, so every element gets a different non-trivial rotation.
struct DeformedBody {
  geometry::TetMesh mesh = test::box_mesh(Eigen::Vector3d(1.0, 0.75, 0.5), 0.25);
  TetBody body{mesh, ElementMaterials::uniform(mesh.tet_count(), kMaterial)};
  RotationField rotations{body, RotationMethod::POLAR};
  Eigen::VectorXd x;
  explicit DeformedBody(unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> jitter(-0.05, 0.05);
    const Eigen::Matrix3d r = test::random_rotation(rng);
    x = body.rest_positions();
    for (int v = 0; v < body.vertex_count(); ++v)
      x.segment<3>(3 * v) =
          r * x.segment<3>(3 * v) + Eigen::Vector3d(jitter(rng), jitter(rng), jitter(rng));
    rotations.update(x);
  }
};

TEST(BrcMatrix, AssemblyMatchesEigenSparseAssembly) {
  const DeformedBody d(21);
  CorotatedAssembler assembler(d.body);
  assembler.assemble(d.rotations);
  std::vector<Eigen::Triplet<double>> triplets;
  for (int e = 0; e < d.body.element_count(); ++e) {
    const Matrix12d k = rotate_stiffness(d.body.stiffness(e), d.rotations.rotation(e));
    for (int i = 0; i < 12; ++i)
      for (int j = 0; j < 12; ++j)
        triplets.emplace_back(3 * d.body.tets()(e, i / 3) + i % 3,
                              3 * d.body.tets()(e, j / 3) + j % 3, k(i, j));
  }
  Eigen::SparseMatrix<double> reference(3 * d.body.vertex_count(), 3 * d.body.vertex_count());
  reference.setFromTriplets(triplets.begin(), triplets.end());
  const Eigen::SparseMatrix<double> brc = assembler.stiffness().to_sparse();
  // Same sums in a different order: round-off of a few ulps of the largest entry.
  EXPECT_LE((brc - reference).norm(), test::kElementRoundoff * reference.norm());
}

TEST(BrcMatrix, DirectReferenceAssemblyEqualsSearchAssembly) {
  const DeformedBody d(22);
  CorotatedAssembler direct(d.body), search(d.body);
  direct.assemble(d.rotations);
  search.assemble_by_search(d.rotations);
  // Same sums in the same element order, but the direct assembly forms Q K_ab Q^T from rotated
  // shape gradients (corotated_assembly.hpp) and the search assembly from the stored K_e:
  // round-off of a few ulps of the largest block.
  double difference = 0.0, norm = 0.0;
  for (int k = 0; k < direct.stiffness().block_count(); ++k) {
    difference =
        std::max(difference, (direct.stiffness().block(k) - search.stiffness().block(k)).norm());
    norm = std::max(norm, direct.stiffness().block(k).norm());
  }
  EXPECT_LE(difference, test::kElementRoundoff * norm);
}

// On a mesh above the parallel thresholds (9 216 tets, ~30k blocks): the parallel gather
// (upper blocks, lower ones mirrored) is the same for 1 and 2 threads, bit for bit, and equals
// the serial element-by-element search assembly to round-off; off-diagonal blocks are exactly
// the transposes of their mirrors.
TEST(BrcMatrix, ParallelAssemblyEqualsSerialAssembly) {
  const geometry::TetMesh mesh = test::box_mesh(Eigen::Vector3d(1.0, 0.75, 0.5), 0.0625);
  const TetBody body(mesh, ElementMaterials::uniform(mesh.tet_count(), kMaterial));
  RotationField rotations(body, RotationMethod::ENERGY_MINIMIZATION);
  std::mt19937 rng(24);
  std::uniform_real_distribution<double> jitter(-0.01, 0.01);
  const Eigen::Matrix3d r = test::random_rotation(rng);
  Eigen::VectorXd x = body.rest_positions();
  for (int v = 0; v < body.vertex_count(); ++v)
    x.segment<3>(3 * v) =
        r * x.segment<3>(3 * v) + Eigen::Vector3d(jitter(rng), jitter(rng), jitter(rng));
  rotations.update(x);
  CorotatedAssembler one(body), two(body), search(body);
  ASSERT_GE(one.stiffness().block_count(), kMinParallelItems);
  const int threads = thread_count();
  set_thread_count(1);
  one.assemble(rotations);
  set_thread_count(2);
  two.assemble(rotations);
  set_thread_count(threads);
  search.assemble_by_search(rotations);
  double difference = 0.0, norm = 0.0;
  const BlockRowMatrix<double>& k = two.stiffness();
  for (int i = 0; i < k.block_rows(); ++i)
    for (int b = k.row_offsets()[i]; b < k.row_offsets()[i + 1]; ++b) {
      ASSERT_EQ(k.block(b), one.stiffness().block(b)) << b;
      if (k.block_columns()[b] != i) {
        ASSERT_EQ(k.block(b), k.block(k.find(k.block_columns()[b], i)).transpose()) << b;
      }
      difference = std::max(difference, (k.block(b) - search.stiffness().block(b)).norm());
      norm = std::max(norm, k.block(b).norm());
    }
  EXPECT_LE(difference, test::kElementRoundoff * norm);
}

TEST(BrcMatrix, ElementReferencesPointAtTheirBlocks) {
  const DeformedBody d(23);
  const CorotatedAssembler assembler(d.body);
  const auto& columns = assembler.stiffness().block_columns();
  const auto& offsets = assembler.stiffness().row_offsets();
  for (int e = 0; e < d.body.element_count(); ++e)
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) {
        const int k = assembler.block_refs()[e][4 * a + b];
        const int row = d.body.tets()(e, a);
        ASSERT_GE(k, offsets[row]);
        ASSERT_LT(k, offsets[row + 1]);
        ASSERT_EQ(columns[k], d.body.tets()(e, b));
      }
}

TEST(BrcMatrix, MultiplyAndDiagonalMatchSparse) {
  const DeformedBody d(24);
  CorotatedAssembler assembler(d.body);
  assembler.assemble(d.rotations);
  const BlockRowMatrix<double>& k = assembler.stiffness();
  std::mt19937 rng(25);
  std::uniform_real_distribution<double> uniform(-1, 1);
  Eigen::VectorXd x(3 * k.block_rows()), y;
  for (int i = 0; i < x.size(); ++i) x[i] = uniform(rng);
  k.multiply(x, y);
  const Eigen::SparseMatrix<double> sparse = k.to_sparse();
  const Eigen::VectorXd reference = sparse * x;
  EXPECT_LE((y - reference).norm(), test::kElementRoundoff * reference.norm());
  const Eigen::MatrixXd dense(sparse);
  for (int i = 0; i < k.block_rows(); ++i)
    EXPECT_EQ((k.diagonal_block(i) - dense.block<3, 3>(3 * i, 3 * i)).norm(), 0.0) << i;
}

TEST(BrcMatrix, FloatMatrixMultipliesLikeDouble) {
  const geometry::TetMesh mesh = test::box_mesh(Eigen::Vector3d(1, 1, 1), 0.5);
  BlockRowMatrix<double> a = tet_block_pattern<double>(mesh.tets, mesh.vertex_count());
  BlockRowMatrix<float> b = tet_block_pattern<float>(mesh.tets, mesh.vertex_count());
  std::mt19937 rng(26);
  std::uniform_real_distribution<double> uniform(-1, 1);
  for (int k = 0; k < a.block_count(); ++k) {
    for (int i = 0; i < 9; ++i) a.block(k)(i) = uniform(rng);
    b.block(k) = a.block(k).cast<float>();
  }
  Eigen::VectorXd x(3 * a.block_rows()), y;
  for (int i = 0; i < x.size(); ++i) x[i] = uniform(rng);
  Eigen::VectorXf yf;
  a.multiply(x, y);
  b.multiply(x.cast<float>(), yf);
  // Single precision: ~1e-7 relative per product, accumulated over ~20 blocks per row.
  EXPECT_LE((yf.cast<double>() - y).norm(), 1e-5 * y.norm());
}

TEST(BrcMatrix, InvalidPatternThrows) {
  EXPECT_THROW(BlockRowMatrix<double>({0, 2, 3}, {1, 0, 1}), Error);  // unsorted row 0
  EXPECT_THROW(BlockRowMatrix<double>({0, 1, 2}, {1, 0}), Error);     // no diagonal blocks
  EXPECT_THROW(BlockRowMatrix<double>({0, 1, 2}, {0, 5}), Error);     // column out of range
}

}  // namespace
}  // namespace mgelastic::tet
