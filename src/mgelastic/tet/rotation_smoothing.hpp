#pragma once
// Spatial smoothing of element rotations (the paper's Sec. 5 comparison method): each element's
// quaternion is replaced by the volume-weighted average over its 1-ring (the elements sharing at
// least one vertex with it, itself included), computed in R^4 and renormalized:
//   q_e <- sum_k w_k s_k q_k / |sum_k w_k s_k q_k|,  w_k = rest volume, s_k = sign(q_e . q_k)
// (s_k picks the representative of +-q_k on the hemisphere of q_e, since q and -q are the same
// rotation).
//
// Layout: the 1-ring is CSR: neighbours of element e are
// neighbours[offsets[e] .. offsets[e+1]), sorted, including e.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace mgelastic::tet {

struct ElementOneRing {
  std::vector<int> offsets;
  std::vector<int> neighbours;
};

ElementOneRing element_one_ring(const Eigen::MatrixX4i& tets, int vertex_count);

// `weights` has one entry per element; `in` and `out` must be different vectors.
void smooth_rotations(const ElementOneRing& ring, const std::vector<double>& weights,
                      const std::vector<Eigen::Quaterniond>& in,
                      std::vector<Eigen::Quaterniond>& out);

}  // namespace mgelastic::tet
