#include "mgelastic/tet/polar_rotation.hpp"

#include <Eigen/LU>
#include <Eigen/SVD>

namespace mgelastic::tet {

Eigen::Matrix3d polar_rotation(const Eigen::Matrix3d& f) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(f, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d u = svd.matrixU();
  const Eigen::Matrix3d v = svd.matrixV();
  // Singular values are sorted decreasingly, so column 2 is the smallest one.
  if ((u * v.transpose()).determinant() < 0.0) u.col(2) = -u.col(2);
  return u * v.transpose();
}

}  // namespace mgelastic::tet
