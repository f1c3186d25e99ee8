#pragma once
// Linear (4-node) tetrahedral element for small-strain elasticity.
//
// Strong form: div sigma + f = 0, sigma = lambda tr(eps) I + 2 mu eps, eps = (grad u + grad u^T)/2
// (Cauchy strain, Hooke's law). Discretization: u = sum_a N_a u_a with linear shape functions;
// grad N_a = g_a is constant per element, so the element energy is exact:
//   W = V (mu eps:eps + lambda/2 tr(eps)^2),  K_ab = V (lambda g_a g_b^T + mu g_b g_a^T
//                                                      + mu (g_a . g_b) I).
// Layout: corners are the columns of a 3x4 matrix; 12-vectors are vertex-major
// (u0x u0y u0z u1x ...); block (a, b) of a 12x12 matrix is rows 3a..3a+2, columns 3b..3b+2.
#include <Eigen/Core>
#include <string>

namespace mgelastic::tet {

using TetCorners = Eigen::Matrix<double, 3, 4>;
using Matrix12d = Eigen::Matrix<double, 12, 12>;
using Vector12d = Eigen::Matrix<double, 12, 1>;

struct ElasticMaterial {
  double youngs_modulus = 1e5;  // Pa
  double poisson_ratio = 0.3;   // in (-1, 0.5)
  double density = 1000.0;      // kg/m^3
};

// Throws Error naming `where` unless E > 0, -1 < nu < 0.5 and density > 0 (all finite).
void check_material(const ElasticMaterial& material, const std::string& where);

// Lame parameters (lambda, mu) of a material.
Eigen::Vector2d lame_parameters(const ElasticMaterial& material);

// Signed volume (positive for the orientation convention of geometry::TetMesh).
double tet_volume(const TetCorners& corners);

// Inverse of the rest edge matrix Dm = [X1-X0, X2-X0, X3-X0]; F = Ds Dm^{-1}.
Eigen::Matrix3d rest_edge_inverse(const TetCorners& rest);

// Gradients of the shape functions: column a = grad N_a (constant over the element).
Eigen::Matrix<double, 3, 4> shape_gradients(const Eigen::Matrix3d& rest_edge_inverse);

// Deformation gradient F = Ds Dm^{-1} of deformed corners x.
Eigen::Matrix3d deformation_gradient(const TetCorners& deformed,
                                     const Eigen::Matrix3d& rest_edge_inverse);

// 12x12 element stiffness (symmetric, PSD, six rigid-motion zero modes).
Matrix12d element_stiffness(const TetCorners& rest, const ElasticMaterial& material);

// Small-strain energy V (mu eps:eps + lambda/2 tr(eps)^2) of displacement gradient H = F - I;
// an independent evaluation used to check the stiffness matrix.
double small_strain_energy(const Eigen::Matrix3d& displacement_gradient, double volume,
                           const ElasticMaterial& material);

}  // namespace mgelastic::tet
