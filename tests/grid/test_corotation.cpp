// Rotation field of the co-rotational model (Sec. 7): exact for rigid rotations, a proper
// rotation for inverted and degenerate cells, never NaN, consistent under restriction.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <random>

#include "mgelastic/grid/coarsening.hpp"
#include "mgelastic/grid/corotation.hpp"

namespace mgelastic::grid {
namespace {

// Orthonormal with determinant +1 to round-off.
void expect_rotation(const Matrix<3>& r) {
  ASSERT_TRUE(r.allFinite());
  EXPECT_LT((r.transpose() * r - Matrix<3>::Identity()).norm(), 1e-12);
  EXPECT_NEAR(r.determinant(), 1.0, 1e-12);
}

TEST(Corotation, PolarRotationOfRandomDeformationsIsTheRotationFactor) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(-0.4, 0.4);
  for (int trial = 0; trial < 100; ++trial) {
    Matrix<3> f = Matrix<3>::Identity();
    for (int a = 0; a < 9; ++a) f.data()[a] += uniform(rng);
    const Eigen::Matrix3d q =
        Eigen::AngleAxisd(3 * uniform(rng),
                          Eigen::Vector3d(uniform(rng), 1, uniform(rng)).normalized())
            .toRotationMatrix();
    const Matrix<3> r = polar_rotation<3>(q * f);
    expect_rotation(r);
    if (f.determinant() <= 0) continue;
    // S = R^T F is symmetric positive definite.
    const Matrix<3> s = r.transpose() * q * f;
    EXPECT_LT((s - s.transpose()).norm(), 1e-12 * s.norm());
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Matrix<3>>(0.5 * (s + s.transpose()))
                  .eigenvalues()
                  .minCoeff(),
              0);
  }
}

TEST(Corotation, InvertedDegenerateAndNonFiniteCellsGiveProperRotations) {
  expect_rotation(polar_rotation<3>(Eigen::Vector3d(-1, 1, 1).asDiagonal()));
  expect_rotation(polar_rotation<3>(Eigen::Vector3d(-1, -1, -1).asDiagonal()));
  expect_rotation(polar_rotation<3>(Matrix<3>::Zero()));
  expect_rotation(polar_rotation<3>(Eigen::Vector3d(1, 1, 0).asDiagonal()));
  Matrix<3> nan = Matrix<3>::Identity();
  nan(1, 2) = std::nan("");
  EXPECT_EQ(polar_rotation<3>(nan), Matrix<3>::Identity());
  // Inverted along one axis: the nearest proper rotation flips the smallest stretch direction.
  const Matrix<3> r = polar_rotation<3>(Eigen::Vector3d(2, 3, -0.5).asDiagonal());
  EXPECT_LT((r - Matrix<3>::Identity()).norm(), 1e-12);
}

Level<3, double> box_level(int n) {
  Lattice<3> lattice(IVec<3>::Constant(n), 1.0 / n);
  std::vector<CellType> cells(lattice.size(), CellType::EXTERIOR);
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(lattice.size()); ++k)
    if (lattice.is_real(lattice.coords(k)))
      cells[k] = lattice.coords(k)[0] == 1 ? CellType::DIRICHLET : CellType::INTERIOR;
  return build_level<3, double>(lattice, cells, Material{1, 0.3}, {}, nullptr);
}

TEST(Corotation, RigidlyRotatedBoxHasItsRotationInEveryCell) {
  Level<3, double> level = box_level(8);
  const Eigen::Matrix3d q =
      Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  // u = (Q - I) X at every active face.
  for (int i = 0; i < 3; ++i)
    for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(level.size()); ++k)
      if (level.kind(i, k) != VarKind::INACTIVE) {
        const Eigen::Vector3d x = level.lattice.face_center(i, k);
        level.x[i][k] = ((q - Matrix<3>::Identity()) * x)[i];
      }
  const auto rotations = cell_rotations(level);
  int checked = 0;
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(level.size()); ++k) {
    if (level.cells[k] != CellType::INTERIOR) continue;
    ASSERT_LT((rotations[k] - q).norm(), 1e-12) << "cell " << k;
    ++checked;
  }
  EXPECT_EQ(checked, 7 * 8 * 8);
  // The restricted field of a uniform rotation is that rotation.
  const Lattice<3> coarse = coarsen(level.lattice);
  const auto coarse_rotations = restrict_rotations(level.lattice, level.cells, rotations, coarse);
  const std::vector<CellType> coarse_cells = coarsen_cells(level.lattice, level.cells);
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(coarse.size()); ++k) {
    if (coarse_cells[k] != CellType::EXTERIOR && coarse.coords(k)[0] > 1) {
      ASSERT_LT((coarse_rotations[k] - q).norm(), 1e-12) << "coarse cell " << k;
    }
  }
}

TEST(Corotation, UniformStretchAndShearHaveNoRotation) {
  // Symmetric displacement gradients: pure stretch and pure (symmetric) shear.
  Level<3, double> level = box_level(8);
  Matrix<3> g;
  g << 0.1, 0.05, 0.0, 0.05, -0.02, 0.03, 0.0, 0.03, 0.04;
  for (int i = 0; i < 3; ++i)
    for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(level.size()); ++k)
      if (level.kind(i, k) != VarKind::INACTIVE)
        level.x[i][k] = (g * level.lattice.face_center(i, k))[i];
  const auto rotations = cell_rotations(level);
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(level.size()); ++k) {
    if (level.cells[k] == CellType::INTERIOR) {
      ASSERT_LT((rotations[k] - Matrix<3>::Identity()).norm(), 1e-12);
      ASSERT_LT((cell_deformation_gradient(level, k) - Matrix<3>::Identity() - g).norm(), 1e-12);
    }
  }
}

}  // namespace
}  // namespace mgelastic::grid
