#include <gtest/gtest.h>

#include <cmath>

#include "mgelastic/grid/box_problem.hpp"
#include "mgelastic/grid/level.hpp"
#include "mgelastic/grid/node_fields.hpp"

namespace mgelastic::grid {
namespace {

// An affine displacement sampled on the staggered faces is reproduced exactly at the nodes,
// by trilinear sampling anywhere inside, and gives the analytic von Mises stress.
TEST(NodeFields, AffineDisplacementIsReproduced) {
  BoxSpec spec;
  spec.cells = 6;
  spec.boundary = BoxBoundary::DIRICHLET;
  const auto problem = make_box_problem<3>(spec);
  const auto level =
      build_level<3, double>(problem.lattice, problem.cells, problem.material, {}, nullptr);
  Eigen::Matrix3d a;
  a << 1e-3, 2e-4, 0, 0, -5e-4, 0, 3e-4, 0, 2e-4;
  auto exact = [&](const Vec<3>& x) -> Vec<3> { return a * x; };
  const NodeDisplacement u = node_displacement<double>(
      level, [&](int f, std::ptrdiff_t k) { return exact(level.lattice.face_center(f, k))[f]; });
  const Vec<3> x(0.31, 0.52, 0.77);
  EXPECT_LT((u.sample(x) - exact(x)).norm(), 1e-15);
  EXPECT_LT((u.at(3, 2, 4) - exact(u.origin + u.h * Vec<3>(3, 2, 4))).norm(), 1e-15);
  const Material m = problem.material;
  const Eigen::Matrix3d strain = 0.5 * (a + a.transpose());
  const Eigen::Matrix3d stress =
      2 * m.mu() * strain + m.lambda() * strain.trace() * Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d dev = stress - stress.trace() / 3 * Eigen::Matrix3d::Identity();
  const double expected = std::sqrt(1.5 * dev.cwiseProduct(dev).sum());
  // Cells away from the lattice's outer layer (there nodes lack symmetric faces).
  const auto stress_field = von_mises_stress(u, m);
  const IVec<3> cells = u.nodes - IVec<3>::Ones();
  for (int k = 1; k < cells[2] - 1; ++k)
    for (int j = 1; j < cells[1] - 1; ++j)
      for (int i = 1; i < cells[0] - 1; ++i)
        EXPECT_NEAR(stress_field[(k * cells[1] + j) * cells[0] + i], expected, 1e-9 * expected);
}

}  // namespace
}  // namespace mgelastic::grid
