// Rotation extraction: energy minimization (Newton on the unit quaternion), polar decomposition
// and polar + 1-ring smoothing.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>

#include "mgelastic/tet/corotated_assembly.hpp"
#include "mgelastic/tet/energy_rotation.hpp"
#include "mgelastic/tet/polar_rotation.hpp"
#include "mgelastic/tet/rotation_field.hpp"
#include "tet/tet_test_support.hpp"

namespace mgelastic::tet {
namespace {

using test::kMaterial;

Eigen::Vector4d wxyz(const Eigen::Quaterniond& q) {
  return {q.w(), q.x(), q.y(), q.z()};
}

// Rotation energy of the paper (Eq. 3) for a deformation gradient F and rest moment S.
struct EnergyCase {
  Eigen::Matrix3d f;
  Eigen::Matrix3d s;
  Eigen::Matrix3d b() const { return f * s; }
  double t() const { return (f * s * f.transpose()).trace(); }
  double energy(const Eigen::Vector4d& q) const {
    return rotation_energy(q, rotation_energy_matrix(b()), t(), s.trace());
  }
};

EnergyCase random_case(std::mt19937& rng, double stretch) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::Matrix3d sym;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j <= i; ++j) sym(i, j) = sym(j, i) = stretch * uniform(rng);
  TetCorners corners;
  for (int a = 0; a < 4; ++a)
    for (int k = 0; k < 3; ++k) corners(k, a) = uniform(rng);
  if (tet_volume(corners) < 0) corners.col(0).swap(corners.col(1));
  return {test::random_rotation(rng) * (Eigen::Matrix3d::Identity() + sym),
          tet_second_moment(corners)};
}

TEST(EnergyRotation, HornMatrixEncodesTraceOfRotatedMoment) {
  std::mt19937 rng(11);
  const EnergyCase c = random_case(rng, 0.3);
  const Eigen::Matrix4d n = rotation_energy_matrix(c.b());
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::Quaterniond q(test::random_rotation(rng));
    const Eigen::Vector4d v = wxyz(q);
    EXPECT_NEAR(v.dot(n * v), (q.toRotationMatrix() * c.b()).trace(), 1e-12 * n.norm());
  }
}

TEST(EnergyRotation, EnergyMatchesDirectIntegralOverVertices) {
  // For a linear tet, int |d|^2 = V/20 (sum |d_a|^2 + |sum d_a|^2) with d affine; check E(q) with
  // the explicit vertex formula.
  std::mt19937 rng(12);
  TetCorners rest;
  rest << 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1;
  const Eigen::Matrix3d f =
      test::random_rotation(rng) * Eigen::Vector3d(1.5, 0.7, 1.1).asDiagonal();
  const TetCorners deformed = f * rest;
  const Eigen::Quaterniond q(test::random_rotation(rng));
  const Eigen::Vector3d c0 = rest.rowwise().mean(), c = deformed.rowwise().mean();
  Eigen::Matrix<double, 3, 4> d;
  for (int a = 0; a < 4; ++a)
    d.col(a) = q.toRotationMatrix() * (deformed.col(a) - c) - (rest.col(a) - c0);
  const double direct =
      tet_volume(rest) / 20.0 * (d.squaredNorm() + d.rowwise().sum().squaredNorm());
  const EnergyCase e{f, tet_second_moment(rest)};
  EXPECT_NEAR(e.energy(wxyz(q)), direct, 1e-12);
}

// A rigidly rotated (and translated) mesh: every method returns the rotation and the corotated
// elastic forces vanish.
TEST(EnergyRotation, RigidRotationRecoveredByAllMethods) {
  const geometry::TetMesh mesh = test::box_mesh(Eigen::Vector3d(1.0, 0.5, 0.5), 0.25);
  const TetBody body(mesh, ElementMaterials::uniform(mesh.tet_count(), kMaterial));
  std::mt19937 rng(13);
  for (RotationMethod method : {RotationMethod::ENERGY_MINIMIZATION, RotationMethod::POLAR,
                                RotationMethod::POLAR_SMOOTHED}) {
    const Eigen::Matrix3d r = test::random_rotation(rng);
    Eigen::VectorXd x(body.rest_positions().size());
    for (int v = 0; v < body.vertex_count(); ++v)
      x.segment<3>(3 * v) = r * body.rest_positions().segment<3>(3 * v) + Eigen::Vector3d(1, 2, 3);
    RotationField field(body, method);
    field.update(x);
    for (int e = 0; e < body.element_count(); ++e)
      ASSERT_LE((field.rotation(e) - r).norm(), test::kRotationExact) << static_cast<int>(method);
    const CorotatedAssembler assembler(body);
    const Eigen::VectorXd f = assembler.elastic_forces(field, x);
    // Forces relative to the stiffness scale times a unit displacement.
    EXPECT_LE(f.norm(), 1e-9 * kMaterial.youngs_modulus) << static_cast<int>(method);
  }
}

// Rotation plus stretch: Newton's answer is the minimizer, checked against a brute-force search
// over 200k random rotations followed by a local refinement of the best sample.
TEST(EnergyRotation, EnergyMinimizationReturnsBruteForceMinimizer) {
  std::mt19937 rng(14);
  for (int trial = 0; trial < 4; ++trial) {
    const EnergyCase c = random_case(rng, 0.4);
    Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
    minimize_rotation_energy(c.b(), c.t(), q);
    const double newton_energy = c.energy(wxyz(q));
    Eigen::Vector4d best = Eigen::Vector4d::UnitX();
    double best_energy = c.energy(best);
    for (int i = 0; i < 200000; ++i) {
      const Eigen::Vector4d v = wxyz(Eigen::Quaterniond(test::random_rotation(rng)));
      const double energy = c.energy(v);
      if (energy < best_energy) best = v, best_energy = energy;
    }
    // Random local search shrinking the radius: the brute-force minimum to ~1e-12.
    std::normal_distribution<double> normal;
    for (double radius = 0.05; radius > 1e-9; radius *= 0.7)
      for (int i = 0; i < 200; ++i) {
        Eigen::Vector4d v =
            best + radius * Eigen::Vector4d(normal(rng), normal(rng), normal(rng), normal(rng));
        v.normalize();
        const double energy = c.energy(v);
        if (energy < best_energy) best = v, best_energy = energy;
      }
    const double scale = c.s.trace() + c.t();
    EXPECT_LE(newton_energy, best_energy + 1e-10 * scale) << trial;
    EXPECT_LE(std::min((wxyz(q) - best).norm(), (wxyz(q) + best).norm()), 1e-4) << trial;
  }
}

TEST(EnergyRotation, NewtonConvergesInAFewStepsFromWarmStart) {
  std::mt19937 rng(15);
  for (int trial = 0; trial < 50; ++trial) {
    const EnergyCase c = random_case(rng, 0.3);
    Eigen::Quaterniond exact = Eigen::Quaterniond::Identity();
    minimize_rotation_energy(c.b(), c.t(), exact);
    // Warm start: the answer perturbed by about 10 degrees, as between two time steps.
    const Eigen::Vector3d axis = test::random_rotation(rng).col(0);
    const Eigen::Quaterniond kick(Eigen::AngleAxisd(0.17, axis));
    Eigen::Quaterniond q = kick * exact;
    const RotationFit fit = minimize_rotation_energy(c.b(), c.t(), q);
    EXPECT_FALSE(fit.fallback) << trial;
    EXPECT_LE(fit.iterations, 6) << trial;
    EXPECT_LE(std::abs(q.angularDistance(exact)), 1e-7) << trial;
  }
}

// The fast path (sphere Newton on B M(q), closed-form LDL^T, early stop after a tiny step) returns
// the minimizer of the reference (q, lambda) Newton of Eqs. 5-8, cold and warm started.
TEST(EnergyRotation, FastPathEqualsTheReferenceNewton) {
  std::mt19937 rng(17);
  int warm_fallbacks = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const EnergyCase c = random_case(rng, 0.4);
    Eigen::Quaterniond exact = Eigen::Quaterniond::Identity();
    minimize_rotation_energy_reference(c.b(), c.t(), exact);
    const double kick_angle = trial % 2 == 0 ? 0.02 : 0.5;
    const Eigen::Quaterniond kick(Eigen::AngleAxisd(kick_angle, test::random_rotation(rng).col(0)));
    for (const Eigen::Quaterniond& start : {Eigen::Quaterniond::Identity(), kick * exact}) {
      Eigen::Quaterniond q = start, reference = start;
      const RotationFit fit = minimize_rotation_energy(c.b(), c.t(), q);
      minimize_rotation_energy_reference(c.b(), c.t(), reference);
      if (start.isApprox(kick * exact)) warm_fallbacks += fit.fallback ? 1 : 0;
      EXPECT_LE(std::abs(q.angularDistance(reference)), 1e-10) << trial;
    }
  }
  EXPECT_EQ(warm_fallbacks, 0);  // warm starts never need the eigen-decomposition
}

// The batched fit (four lanes, vector code) returns the scalar fit's rotation in every lane: warm
// and cold starts, lanes mixed with degenerate ones (collapsed, inverted, flat, non-unit or
// non-finite warm start) that the batch hands to the scalar path.
TEST(EnergyRotation, BatchEqualsTheScalarFit) {
  std::mt19937 rng(19);
  TetCorners rest;
  rest << 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1;
  const Eigen::Matrix3d s = tet_second_moment(rest);
  const std::vector<Eigen::Matrix3d> degenerate = {
      Eigen::Matrix3d::Zero(), Eigen::Vector3d(1, 1, -1).asDiagonal(),
      Eigen::Vector3d(1, 1, 0).asDiagonal(), 1e8 * Eigen::Matrix3d::Identity()};
  int newton_lanes = 0;
  for (int trial = 0; trial < 100; ++trial) {
    RotationFitBatch batch;
    std::array<Eigen::Matrix3d, kRotationLanes> moments;
    std::array<double, kRotationLanes> traces;
    std::array<Eigen::Quaterniond, kRotationLanes> starts;
    for (int l = 0; l < kRotationLanes; ++l) {
      EnergyCase c = random_case(rng, 0.4);
      if ((trial + l) % 7 == 0) c = {test::random_rotation(rng) * degenerate[trial % 4], s};
      moments[l] = c.b();
      traces[l] = c.t();
      Eigen::Quaterniond exact = Eigen::Quaterniond::Identity();
      minimize_rotation_energy_reference(c.b(), c.t(), exact);
      const Eigen::Quaterniond kick(Eigen::AngleAxisd(0.05, test::random_rotation(rng).col(0)));
      starts[l] = trial % 3 == 0 ? Eigen::Quaterniond::Identity() : kick * exact;
      if ((trial + 2 * l) % 11 == 0) starts[l].coeffs() *= 3.0;  // non-unit warm start
      if ((trial + 3 * l) % 13 == 0) starts[l].coeffs().setConstant(NAN);
      for (int k = 0; k < 9; ++k) batch.moment[k][l] = moments[l](k / 3, k % 3);
      batch.deformed_moment[l] = traces[l];
      batch.q[0][l] = starts[l].w(), batch.q[1][l] = starts[l].x();
      batch.q[2][l] = starts[l].y(), batch.q[3][l] = starts[l].z();
    }
    minimize_rotation_energy(batch);
    for (int l = 0; l < kRotationLanes; ++l) {
      Eigen::Quaterniond scalar = starts[l];
      const RotationFit fit = minimize_rotation_energy(moments[l], traces[l], scalar);
      const Eigen::Quaterniond q(batch.q[0][l], batch.q[1][l], batch.q[2][l], batch.q[3][l]);
      ASSERT_TRUE(q.coeffs().allFinite()) << trial << " " << l;
      EXPECT_NEAR(q.norm(), 1.0, 1e-12) << trial << " " << l;
      EXPECT_LE((wxyz(q) - wxyz(scalar)).norm(), 1e-12) << trial << " " << l;
      EXPECT_EQ(batch.fits[l].fallback, fit.fallback) << trial << " " << l;
      newton_lanes += fit.fallback ? 0 : 1;
    }
  }
  EXPECT_GT(newton_lanes, 200);  // the cases are mostly regular (not eigen-decomposition answers)
}

// Positions of `body` bent (y += 0.3 x^2), rotated by a random rotation and jittered by up to
// 0.02 per coordinate.
Eigen::VectorXd bent_rotated_jittered(const TetBody& body, std::mt19937& rng) {
  std::uniform_real_distribution<double> jitter(-0.02, 0.02);
  const Eigen::Matrix3d r = test::random_rotation(rng);
  Eigen::VectorXd x(body.rest_positions().size());
  for (int v = 0; v < body.vertex_count(); ++v) {
    const Eigen::Vector3d p = body.rest_positions().segment<3>(3 * v);
    x.segment<3>(3 * v) = r * Eigen::Vector3d(p[0], p[1] + 0.3 * p[0] * p[0], p[2]) +
                          Eigen::Vector3d(jitter(rng), jitter(rng), jitter(rng));
  }
  return x;
}

// RotationField takes B and T from centroid offsets (B = D R^T, T = V/20 |D|^2); the reference
// takes them from F and the rest moment S. Same rotations on a randomly deformed mesh.
TEST(EnergyRotation, FieldUpdateEqualsPerElementReference) {
  const geometry::TetMesh mesh = test::box_mesh(Eigen::Vector3d(1.0, 0.5, 0.5), 0.125);
  const TetBody body(mesh, ElementMaterials::uniform(mesh.tet_count(), kMaterial));
  std::mt19937 rng(18);
  const Eigen::VectorXd x = bent_rotated_jittered(body, rng);
  RotationField field(body, RotationMethod::ENERGY_MINIMIZATION);
  field.update(x);
  for (int e = 0; e < body.element_count(); ++e) {
    const Eigen::Matrix3d f = deformation_gradient(body.corners(e, x), body.rest_edge_inverse(e));
    const Eigen::Matrix3d b = f * body.second_moment(e);
    Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
    minimize_rotation_energy_reference(b, (b * f.transpose()).trace(), q);
    ASSERT_LE(std::abs(field.quaternions()[e].angularDistance(q.conjugate())), 1e-9) << e;
  }
}

// RotationField's POLAR runs the quaternion fit with B = F; it equals the SVD polar rotation of F
// per element, on a smoothly bent and rotated mesh with a few inverted elements, cold (identity)
// and warm (previous update) started.
TEST(EnergyRotation, PolarFieldEqualsTheSvdPolar) {
  const geometry::TetMesh mesh = test::box_mesh(Eigen::Vector3d(1.0, 0.5, 0.5), 0.125);
  const TetBody body(mesh, ElementMaterials::uniform(mesh.tet_count(), kMaterial));
  std::mt19937 rng(20);
  RotationField field(body, RotationMethod::POLAR);
  for (int update = 0; update < 2; ++update) {
    Eigen::VectorXd x = bent_rotated_jittered(body, rng);
    // Swapping two corners of element 0 inverts it.
    const Eigen::Vector3d corner = x.segment<3>(3 * body.tets()(0, 0));
    x.segment<3>(3 * body.tets()(0, 0)) = x.segment<3>(3 * body.tets()(0, 1));
    x.segment<3>(3 * body.tets()(0, 1)) = corner;
    field.update(x);
    int inverted = 0;
    for (int e = 0; e < body.element_count(); ++e) {
      const Eigen::Matrix3d f = deformation_gradient(body.corners(e, x), body.rest_edge_inverse(e));
      inverted += f.determinant() < 0.0 ? 1 : 0;
      const Eigen::Matrix3d svd = polar_rotation(f);
      ASSERT_LE((field.rotation(e) - svd).norm(), 1e-9) << "element " << e << " update " << update;
    }
    EXPECT_GT(inverted, 0);
  }
}

// Degenerate deformations: inverted, flat, collinear, collapsed, huge. The quaternion stays unit
// and finite, and (where defined) it is the minimizer: the top eigenvector of N.
TEST(EnergyRotation, NeverNonUnitOrNanOnInvertedAndFlatElements) {
  std::mt19937 rng(16);
  TetCorners rest;
  rest << 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1;
  const Eigen::Matrix3d s = tet_second_moment(rest);
  std::vector<Eigen::Matrix3d> maps = {
      Eigen::Vector3d(1, 1, -1).asDiagonal(),      // inverted (mirrored)
      Eigen::Vector3d(2, 0.5, -0.3).asDiagonal(),  // inverted and stretched
      Eigen::Vector3d(1, 1, 0).asDiagonal(),       // flat
      Eigen::Vector3d(1, 0, 0).asDiagonal(),       // collinear
      Eigen::Matrix3d::Zero(),                     // collapsed to a point
      1e8 * test::random_rotation(rng) * Eigen::Vector3d(3, 1, 2).asDiagonal(),    // huge
      1e-9 * test::random_rotation(rng) * Eigen::Vector3d(3, 1, 2).asDiagonal()};  // tiny
  for (std::size_t i = 0; i < maps.size(); ++i) {
    for (int start = 0; start < 20; ++start) {
      const Eigen::Matrix3d f = test::random_rotation(rng) * maps[i];
      const EnergyCase c{f, s};
      Eigen::Quaterniond q(test::random_rotation(rng));
      minimize_rotation_energy(c.b(), c.t(), q);
      ASSERT_TRUE(q.coeffs().allFinite()) << i;
      ASSERT_NEAR(q.norm(), 1.0, 1e-12) << i;
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eigen(rotation_energy_matrix(c.b()));
      const Eigen::Vector4d v = wxyz(q);
      const double top = eigen.eigenvalues()[3];
      EXPECT_GE(v.dot(rotation_energy_matrix(c.b()) * v), top - 1e-9 * (std::abs(top) + 1e-300))
          << i;
    }
  }
}

TEST(EnergyRotation, PolarRotationIsProperForReflections) {
  const Eigen::Matrix3d r = polar_rotation(Eigen::Vector3d(2, 1, -0.5).asDiagonal());
  EXPECT_NEAR(r.determinant(), 1.0, 1e-12);
  EXPECT_LE((r * r.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_TRUE(polar_rotation(Eigen::Matrix3d::Zero()).allFinite());
}

TEST(EnergyRotation, SmoothingAveragesNeighboursByVolume) {
  // Two elements sharing a vertex: rotations about z by 0 and 0.2 rad (with a sign flip on the
  // second quaternion, which must not matter) and volumes 1 and 3 average to 0.15 rad.
  Eigen::MatrixX4i tets(2, 4);
  tets << 0, 1, 2, 3, 3, 4, 5, 6;
  const ElementOneRing ring = element_one_ring(tets, 7);
  ASSERT_EQ(ring.offsets[1] - ring.offsets[0], 2);
  std::vector<Eigen::Quaterniond> in = {
      Eigen::Quaterniond::Identity(),
      Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()))};
  in[1].coeffs() *= -1.0;
  std::vector<Eigen::Quaterniond> out;
  smooth_rotations(ring, {1.0, 3.0}, in, out);
  // Quaternion averaging equals angle averaging up to O(angle^3): tan(a)=3 sin(0.1)/(1+3cos(0.1)).
  const double expected = 2.0 * std::atan2(3.0 * std::sin(0.1), 1.0 + 3.0 * std::cos(0.1));
  EXPECT_NEAR(Eigen::AngleAxisd(out[0]).angle(), expected, 1e-12);
}

}  // namespace
}  // namespace mgelastic::tet
