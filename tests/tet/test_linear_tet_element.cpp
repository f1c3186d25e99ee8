// Linear tetrahedral element: symmetry, rigid modes, energy gradient, patch test.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <random>

#include "mgelastic/tet/block_jacobi_pcg.hpp"
#include "mgelastic/tet/corotated_assembly.hpp"
#include "mgelastic/tet/corotated_solver.hpp"
#include "mgelastic/tet/linear_tet_element.hpp"
#include "tet/tet_test_support.hpp"

namespace mgelastic::tet {
namespace {

using test::kMaterial;

// A random, reasonably shaped, positively oriented tetrahedron.
TetCorners random_tet(std::mt19937& rng) {
  std::uniform_real_distribution<double> jitter(-0.2, 0.2);
  TetCorners c;
  c << 0, 1, 0, 0,  //
      0, 0, 1, 0,   //
      0, 0, 0, 1;
  for (int a = 0; a < 4; ++a)
    for (int k = 0; k < 3; ++k) c(k, a) += jitter(rng);
  return c;
}

TEST(LinearTetElement, StiffnessIsSymmetric) {
  std::mt19937 rng(1);
  const Matrix12d k = element_stiffness(random_tet(rng), kMaterial);
  EXPECT_LE((k - k.transpose()).norm(), test::kElementRoundoff * k.norm());
}

TEST(LinearTetElement, StiffnessIsPsdWithExactlySixZeroModes) {
  std::mt19937 rng(2);
  for (int trial = 0; trial < 5; ++trial) {
    const Matrix12d k = element_stiffness(random_tet(rng), kMaterial);
    const Eigen::SelfAdjointEigenSolver<Matrix12d> eigen(k);
    const Eigen::VectorXd values = eigen.eigenvalues();  // ascending
    const double largest = values[11];
    // Zero modes are zero up to round-off of |K|; the elastic modes of a reasonable shape are
    // well separated from it (the smallest one is O(1e-2) of the largest).
    for (int i = 0; i < 6; ++i) EXPECT_LE(std::abs(values[i]), 1e-10 * largest) << i;
    for (int i = 6; i < 12; ++i) EXPECT_GT(values[i], 1e-4 * largest) << i;
  }
}

TEST(LinearTetElement, RigidMotionsAreZeroModes) {
  std::mt19937 rng(3);
  const TetCorners x = random_tet(rng);
  const Matrix12d k = element_stiffness(x, kMaterial);
  const Eigen::Vector3d omega(0.3, -0.2, 0.5), shift(1.0, 2.0, -1.0);
  Vector12d u;
  for (int a = 0; a < 4; ++a) u.segment<3>(3 * a) = shift + omega.cross(Eigen::Vector3d(x.col(a)));
  EXPECT_LE((k * u).norm(), test::kElementRoundoff * k.norm() * u.norm());
}

TEST(LinearTetElement, ForceIsFiniteDifferenceGradientOfEnergy) {
  std::mt19937 rng(4);
  const TetCorners rest = random_tet(rng);
  const Matrix12d k = element_stiffness(rest, kMaterial);
  const Eigen::Matrix3d dm_inverse = rest_edge_inverse(rest);
  const double volume = tet_volume(rest);
  // Energy evaluated independently from the strain tensor, not from K.
  const auto energy = [&](const Vector12d& u) {
    const TetCorners x = rest + u.reshaped(3, 4);
    return small_strain_energy(deformation_gradient(x, dm_inverse) - Eigen::Matrix3d::Identity(),
                               volume, kMaterial);
  };
  std::uniform_real_distribution<double> uniform(-0.1, 0.1);
  Vector12d u;
  for (int i = 0; i < 12; ++i) u[i] = uniform(rng);
  const Vector12d force = -k * u;
  const double step = 1e-6;
  for (int i = 0; i < 12; ++i) {
    Vector12d plus = u, minus = u;
    plus[i] += step;
    minus[i] -= step;
    const double gradient = (energy(plus) - energy(minus)) / (2 * step);
    EXPECT_NEAR(-gradient, force[i], test::kFiniteDifference * force.norm()) << i;
  }
}

// Affine displacement u = A X + c imposed on the boundary of a box: the interior vertices of the
// assembled linear system must reproduce it to solver precision (constant strain is exact).
TEST(LinearTetElement, PatchTestReproducesAffineDisplacement) {
  const geometry::TetMesh mesh = test::box_mesh(Eigen::Vector3d(1, 1, 1), 0.25);
  const TetBody body(mesh, ElementMaterials::uniform(mesh.tet_count(), kMaterial));
  CorotatedAssembler assembler(body);
  const RotationField identity(body, RotationMethod::POLAR);  // never updated: Q = I
  assembler.assemble(identity);
  Eigen::Matrix3d a;
  a << 0.01, 0.02, -0.01, 0.005, -0.02, 0.01, 0.0, 0.03, 0.01;
  const Eigen::Vector3d c(0.1, -0.2, 0.3);
  std::vector<char> boundary(body.vertex_count(), 0);
  Eigen::VectorXd exact(3 * body.vertex_count());
  int interior = 0;
  for (int v = 0; v < body.vertex_count(); ++v) {
    const Eigen::Vector3d x = mesh.vertices.row(v).transpose();
    exact.segment<3>(3 * v) = a * x + c;
    boundary[v] = (x.minCoeff() < 1e-12 || x.maxCoeff() > 1 - 1e-12) ? 1 : 0;
    interior += boundary[v] ? 0 : 1;
  }
  ASSERT_EQ(interior, 27);
  const StepSystem system(assembler.stiffness(), body.vertex_mass(), 0.0, 1.0, boundary);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(exact.size());
  system.eliminate(exact, b);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(exact.size());
  const PcgResult result = solve_pcg(system, b, u, PcgSettings{1e-13, 1000});
  ASSERT_TRUE(result.converged);
  // PCG to 1e-13 relative residual on a well-conditioned 81-unknown system.
  EXPECT_LE((u - exact).lpNorm<Eigen::Infinity>(), 1e-10 * exact.lpNorm<Eigen::Infinity>());
}

// Corotated patch test: x = R (I + S) X + c with a small symmetric stretch S. Polar rotations are
// the same R in every element, so the corotated forces are the linear ones of an affine field and
// the static solve must reproduce x in the interior.
TEST(LinearTetElement, CorotatedPatchTestWithPolarRotations) {
  const geometry::TetMesh mesh = test::box_mesh(Eigen::Vector3d(1, 1, 1), 0.25);
  CorotatedSolverSettings settings;
  settings.rotation_method = RotationMethod::POLAR;
  settings.linear_solver = LinearSolver::CHOLESKY;
  CorotatedSolver solver(mesh, ElementMaterials::uniform(mesh.tet_count(), kMaterial), settings);
  std::mt19937 rng(5);
  const Eigen::Matrix3d r = test::random_rotation(rng);
  Eigen::Matrix3d s;
  s << 0.02, 0.01, 0.0, 0.01, -0.01, 0.005, 0.0, 0.005, 0.03;
  const Eigen::Matrix3d map = r * (Eigen::Matrix3d::Identity() + s);
  const Eigen::Vector3d c(0.5, 0.1, -0.3);
  std::vector<int> boundary;
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    const Eigen::Vector3d x = mesh.vertices.row(v).transpose();
    if (x.minCoeff() < 1e-12 || x.maxCoeff() > 1 - 1e-12) boundary.push_back(v);
  }
  solver.set_dirichlet(boundary, [&](int, const Eigen::Vector3d& x, double) {
    return Eigen::Vector3d(map * x + c);
  });
  solver.solve_static(30, 1e-13);
  double error = 0.0;
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    const Eigen::Vector3d expected = map * mesh.vertices.row(v).transpose() + c;
    error = std::max(error, (solver.positions().segment<3>(3 * v) - expected).norm());
  }
  // Fixed-point iteration on the rotations converges linearly; 1e-9 of the O(1) positions.
  EXPECT_LE(error, 1e-9);
}

}  // namespace
}  // namespace mgelastic::tet
