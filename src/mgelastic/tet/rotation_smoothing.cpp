#include "mgelastic/tet/rotation_smoothing.hpp"
#include "mgelastic/tet/parallel.hpp"

#include <algorithm>

namespace mgelastic::tet {

ElementOneRing element_one_ring(const Eigen::MatrixX4i& tets, int vertex_count) {
  // Vertex -> elements (CSR) first, then the union over each element's four vertices.
  std::vector<int> vertex_offsets(vertex_count + 1, 0);
  for (int e = 0; e < tets.rows(); ++e)
    for (int a = 0; a < 4; ++a) ++vertex_offsets[tets(e, a) + 1];
  for (int v = 0; v < vertex_count; ++v) vertex_offsets[v + 1] += vertex_offsets[v];
  std::vector<int> vertex_elements(vertex_offsets.back());
  std::vector<int> fill(vertex_offsets.begin(), vertex_offsets.end() - 1);
  for (int e = 0; e < tets.rows(); ++e)
    for (int a = 0; a < 4; ++a) vertex_elements[fill[tets(e, a)]++] = e;

  ElementOneRing ring;
  ring.offsets.reserve(tets.rows() + 1);
  ring.offsets.push_back(0);
  std::vector<int> scratch;
  for (int e = 0; e < tets.rows(); ++e) {
    scratch.clear();
    for (int a = 0; a < 4; ++a) {
      const int v = tets(e, a);
      scratch.insert(scratch.end(), vertex_elements.begin() + vertex_offsets[v],
                     vertex_elements.begin() + vertex_offsets[v + 1]);
    }
    std::sort(scratch.begin(), scratch.end());
    scratch.erase(std::unique(scratch.begin(), scratch.end()), scratch.end());
    ring.neighbours.insert(ring.neighbours.end(), scratch.begin(), scratch.end());
    ring.offsets.push_back(static_cast<int>(ring.neighbours.size()));
  }
  return ring;
}

void smooth_rotations(const ElementOneRing& ring, const std::vector<double>& weights,
                      const std::vector<Eigen::Quaterniond>& in,
                      std::vector<Eigen::Quaterniond>& out) {
  const int count = static_cast<int>(in.size());
  out.resize(count);
#pragma omp parallel for schedule(static) if (count >= kMinParallelElements)
  for (int e = 0; e < count; ++e) {
    const Eigen::Vector4d own = in[e].coeffs();
    Eigen::Vector4d sum = Eigen::Vector4d::Zero();
    for (int k = ring.offsets[e]; k < ring.offsets[e + 1]; ++k) {
      const int other = ring.neighbours[k];
      const Eigen::Vector4d q = in[other].coeffs();
      sum += (q.dot(own) < 0.0 ? -weights[other] : weights[other]) * q;
    }
    // The own term has positive weight and the aligned terms cannot cancel it completely
    // unless the neighbours disagree wildly; keep the element's own rotation then.
    const double norm = sum.norm();
    out[e] = norm > 1e-12 * weights[e] ? Eigen::Quaterniond(sum / norm) : in[e];
  }
}

}  // namespace mgelastic::tet
