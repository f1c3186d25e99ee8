#pragma once
// Helpers shared by the tet tests: temporary directories, small meshes, stated tolerances.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "mgelastic/geometry/tet_mesh.hpp"
#include "mgelastic/geometry/tet_mesh_grid.hpp"
#include "mgelastic/tet/linear_tet_element.hpp"

#include "support/temp_dir.hpp"

namespace mgelastic::test {

// The tet tests' default material: E = 1e5 Pa, nu = 0.3, density 1000 kg/m^3.
inline const tet::ElasticMaterial kMaterial{1e5, 0.3, 1000.0};

// Round-off of a 12x12 element computation in double, relative to |K|: a few hundred ulps.
inline constexpr double kElementRoundoff = 1e-12;
// Rotation extracted from an exactly rotated element: SVD / Newton converge to machine precision;
// the issue asks for 1e-10.
inline constexpr double kRotationExact = 1e-10;
// Central finite differences with step 1e-6 on O(1) quantities: truncation ~1e-12, round-off
// ~1e-16/1e-6 = 1e-10, so 1e-6 relative leaves a wide margin.
inline constexpr double kFiniteDifference = 1e-6;

// Axis-aligned box [0, size] split into cubes of edge h (Kuhn split), all cubes kept.
inline geometry::TetMesh box_mesh(const Eigen::Vector3d& size, double h) {
  return geometry::regular_tet_grid([](const Eigen::Vector3d&) { return true; },
                                    Eigen::AlignedBox3d(Eigen::Vector3d::Zero(), size), h)
      .mesh;
}

// A random rotation from a seeded generator (uniform quaternion, normalized Gaussian).
inline Eigen::Matrix3d random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> normal;
  Eigen::Vector4d q(normal(rng), normal(rng), normal(rng), normal(rng));
  q.normalize();
  return Eigen::Quaterniond(q[0], q[1], q[2], q[3]).toRotationMatrix();
}

}  // namespace mgelastic::test
