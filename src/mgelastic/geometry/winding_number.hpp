#pragma once
// Generalized winding number of a triangle surface (Jacobson, Kavan, Sorkine-Hornung 2013),
//
//   w(q) = 1/(4 pi) sum_t Omega_t(q),
//
// where Omega_t is the signed solid angle of triangle t seen from q (Van Oosterom-Strackee):
//   tan(Omega/2) = a.(b x c) / (|a||b||c| + (a.b)|c| + (b.c)|a| + (c.a)|b|),  a, b, c = corners -
//   q.
// For a closed, outward-oriented surface w is 1 inside and 0 outside; for surfaces with holes or
// non-manifold parts it degrades smoothly, which makes w > 1/2 a robust inside test.
//
// Hierarchical evaluation (Barill, Dickson, Schmidt, Levin, Jacobson 2018, "Fast Winding Numbers
// for Soups and Clouds"): with F(x) = (x - q) / (4 pi |x - q|^3), the solid angle of a patch is
// w = int F(x).n dA. Each node of the triangle BVH stores its area-weighted centroid p, radius r
// (the farthest corner from p) and the moments of its triangles t (area a_t, unit normal n_t,
// d = x - p):
//   N = sum_t a_t n_t,   M_ij = sum_t n_t,i int_t d_j dA,   S_ijk = sum_t n_t,i int_t d_j d_k dA
// (the integrals are exact: a_t (c_t - p) and a_t/12 (sum_v d_v d_v^T + s s^T), s = sum_v d_v).
// When |q - p| > beta r the node contributes the Taylor expansion of F about p,
//   w_node ~ F_i N_i + dF_i/dx_j M_ij + 1/2 d2F_i/dx_j dx_k S_ijk,
//   4 pi F_i = r_i / |r|^3,   4 pi dF_i/dx_j = d_ij / |r|^3 - 3 r_i r_j / |r|^5,
//   4 pi d2F_i/dx_j dx_k = -3 (d_ij r_k + d_ik r_j + d_jk r_i) / |r|^5 + 15 r_i r_j r_k / |r|^7,
// with r = p - q; otherwise its children (or, at a leaf, its triangles exactly) are visited.
// Because p is the area-weighted centroid, M vanishes for flat patches: the second-order term
// is what buys accuracy. The far-field error falls like beta^-4: measured against the exact sum
// on random points (icosphere, bunny, armadillo), beta = 2 gives a mean error of 0.7e-3..1e-3
// and a worst of 3e-3..5e-3; beta = 3 a worst below 1e-3 at about half the speed.
#include <memory>
#include <vector>

#include "mgelastic/geometry/triangle_bvh.hpp"

namespace mgelastic::geometry {

// Signed solid angle (steradians, in [-2 pi, 2 pi]) of triangle abc seen from q; positive when
// q sees the triangle counter-clockwise, i.e. q is behind its right-hand normal.
double triangle_solid_angle(const Point& a, const Point& b, const Point& c, const Point& q);

// The exact sum over all triangles (O(T) per query): the reference for tests.
double exact_winding_number(const TriangleMesh& mesh, const Point& q);

// Taylor order of the far-field expansion: the dipole F.N alone, + M, + S (libigl's default).
enum class ExpansionOrder { DIPOLE, FIRST, SECOND };

struct WindingNumberOptions {
  double beta = 2.0;  // far field when |q - p| > beta * r (Barill et al.'s choice)
  ExpansionOrder order = ExpansionOrder::SECOND;
};

class WindingNumber {
 public:
  // `bvh` is shared (e.g. with the distance query of MeshShape).
  explicit WindingNumber(std::shared_ptr<const TriangleBvh> bvh, WindingNumberOptions options = {});
  // Builds its own BVH; `mesh` must be checked (check_triangle_mesh) and non-empty.
  explicit WindingNumber(const TriangleMesh& mesh, WindingNumberOptions options = {});

  // Hierarchical approximation of w(q); thread-safe.
  double operator()(const Point& q) const;
  const TriangleBvh& bvh() const { return *m_bvh; }

 private:
  // Far-field data of one BVH node (indexed like TriangleBvh::nodes()).
  struct Expansion {
    Eigen::Vector3d center = Eigen::Vector3d::Zero();
    double radius = 0.0;
    Eigen::Vector3d dipole = Eigen::Vector3d::Zero();
    Eigen::Matrix3d moment = Eigen::Matrix3d::Zero();                  // M
    std::array<Eigen::Matrix3d, 3> second = {Eigen::Matrix3d::Zero(),  // S_i.. for i = 0, 1, 2
                                             Eigen::Matrix3d::Zero(), Eigen::Matrix3d::Zero()};
  };

  Expansion expand(const TriangleBvh::Node& node) const;
  double far_field(const Expansion& e, const Point& q) const;

  std::shared_ptr<const TriangleBvh> m_bvh;
  WindingNumberOptions m_options;
  std::vector<Expansion> m_expansions;
};

}  // namespace mgelastic::geometry
