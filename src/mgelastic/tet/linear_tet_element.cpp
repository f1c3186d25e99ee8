#include "mgelastic/tet/linear_tet_element.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>

#include "mgelastic/core/error.hpp"

namespace mgelastic::tet {

void check_material(const ElasticMaterial& material, const std::string& where) {
  const auto fail = [&](const std::string& reason) {
    throw Error(reason, ErrorContext{std::string(), -1, where});
  };
  if (!(material.youngs_modulus > 0.0) || !std::isfinite(material.youngs_modulus))
    fail("Young's modulus must be positive and finite");
  if (!(material.poisson_ratio > -1.0 && material.poisson_ratio < 0.5))
    fail("Poisson ratio must lie in (-1, 0.5)");
  if (!(material.density > 0.0) || !std::isfinite(material.density))
    fail("density must be positive and finite");
}

Eigen::Vector2d lame_parameters(const ElasticMaterial& material) {
  const double e = material.youngs_modulus;
  const double nu = material.poisson_ratio;
  return {e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), e / (2.0 * (1.0 + nu))};
}

double tet_volume(const TetCorners& c) {
  return (c.col(1) - c.col(0)).dot((c.col(2) - c.col(0)).cross(c.col(3) - c.col(0))) / 6.0;
}

Eigen::Matrix3d rest_edge_inverse(const TetCorners& rest) {
  Eigen::Matrix3d dm;
  for (int a = 0; a < 3; ++a) dm.col(a) = rest.col(a + 1) - rest.col(0);
  return dm.inverse();
}

Eigen::Matrix<double, 3, 4> shape_gradients(const Eigen::Matrix3d& dm_inverse) {
  // N_a for a = 1..3 are the barycentric coordinates Dm^{-1} (X - X0), so their gradients are
  // the rows of Dm^{-1}; N_0 = 1 - N_1 - N_2 - N_3.
  Eigen::Matrix<double, 3, 4> g;
  g.rightCols<3>() = dm_inverse.transpose();
  g.col(0) = -g.rightCols<3>().rowwise().sum();
  return g;
}

Eigen::Matrix3d deformation_gradient(const TetCorners& x, const Eigen::Matrix3d& dm_inverse) {
  Eigen::Matrix3d ds;
  for (int a = 0; a < 3; ++a) ds.col(a) = x.col(a + 1) - x.col(0);
  return ds * dm_inverse;
}

Matrix12d element_stiffness(const TetCorners& rest, const ElasticMaterial& material) {
  const Eigen::Matrix<double, 3, 4> g = shape_gradients(rest_edge_inverse(rest));
  const double volume = std::abs(tet_volume(rest));
  const Eigen::Vector2d lame = lame_parameters(material);
  Matrix12d k;
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b) {
      k.block<3, 3>(3 * a, 3 * b) =
          volume *
          (lame[0] * g.col(a) * g.col(b).transpose() + lame[1] * g.col(b) * g.col(a).transpose() +
           lame[1] * g.col(a).dot(g.col(b)) * Eigen::Matrix3d::Identity());
    }
  return k;
}

double small_strain_energy(const Eigen::Matrix3d& h, double volume,
                           const ElasticMaterial& material) {
  const Eigen::Matrix3d eps = 0.5 * (h + h.transpose());
  const Eigen::Vector2d lame = lame_parameters(material);
  return volume * (lame[1] * eps.squaredNorm() + 0.5 * lame[0] * eps.trace() * eps.trace());
}

}  // namespace mgelastic::tet
