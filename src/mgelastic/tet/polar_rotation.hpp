#pragma once
// Element rotation from the polar decomposition of the deformation gradient F = R U
// (Hauth & Strasser 2004, the paper's comparison method).
//
// R = U_svd V_svd^T from F = U_svd Sigma V_svd^T. When det(U V^T) < 0 (an inverted element, or
// round-off on a flat one) the column of U belonging to the smallest singular value is negated,
// which gives the closest proper rotation (det R = +1). Never returns NaN for finite F; F = 0
// gives some rotation.
#include <Eigen/Core>

namespace mgelastic::tet {

Eigen::Matrix3d polar_rotation(const Eigen::Matrix3d& deformation_gradient);

}  // namespace mgelastic::tet
