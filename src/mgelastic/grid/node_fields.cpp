#include "mgelastic/grid/node_fields.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

namespace mgelastic::grid {

Vec<3> NodeDisplacement::at(int i, int j, int k) const {
  const std::size_t n = (std::size_t(k) * nodes[1] + j) * nodes[0] + i;
  return Vec<3>(values[3 * n], values[3 * n + 1], values[3 * n + 2]);
}

Vec<3> NodeDisplacement::sample(const Vec<3>& x) const {
  Vec<3> t = (x - origin) / h;
  IVec<3> base;
  for (int a = 0; a < 3; ++a) {
    t[a] = std::clamp(t[a], 0.0, double(nodes[a] - 1));
    base[a] = std::min(static_cast<int>(std::floor(t[a])), nodes[a] - 2);
    t[a] -= base[a];
  }
  Vec<3> result = Vec<3>::Zero();
  for (int c = 0; c < 8; ++c) {
    const int dx = c & 1, dy = (c >> 1) & 1, dz = (c >> 2) & 1;
    const double w = (dx ? t[0] : 1 - t[0]) * (dy ? t[1] : 1 - t[1]) * (dz ? t[2] : 1 - t[2]);
    result += w * at(base[0] + dx, base[1] + dy, base[2] + dz);
  }
  return result;
}

namespace {

// Nodes no active face touches would read as zero displacement and drag interpolants that reach
// past the body (tricubic uses one more node layer) toward rest; give them, layer by layer, the
// mean of their defined 6-neighbors instead (a constant extension of the body's motion).
void extend_into_empty_nodes(NodeDisplacement& u, std::vector<char>& defined, int layers) {
  const auto id = [&](int i, int j, int k) {
    return (std::size_t(k) * u.nodes[1] + j) * u.nodes[0] + i;
  };
  for (int layer = 0; layer < layers; ++layer) {
    std::vector<char> next = defined;
    // A node of this layer is written once and reads only nodes defined before it: parallel.
#pragma omp parallel for schedule(static)
    for (int k = 0; k < u.nodes[2]; ++k)
      for (int j = 0; j < u.nodes[1]; ++j)
        for (int i = 0; i < u.nodes[0]; ++i)
          for (int a = 0; a < 3; ++a) {
            const std::size_t n = id(i, j, k);
            if (defined[3 * n + a]) continue;
            double sum = 0;
            int count = 0;
            for (int axis = 0; axis < 3; ++axis)
              for (int step : {-1, 1}) {
                IVec<3> q(i, j, k);
                q[axis] += step;
                if (q[axis] < 0 || q[axis] >= u.nodes[axis]) continue;
                const std::size_t m = id(q[0], q[1], q[2]);
                if (!defined[3 * m + a]) continue;
                sum += u.values[3 * m + a];
                ++count;
              }
            if (count == 0) continue;
            u.values[3 * n + a] = sum / count;
            next[3 * n + a] = 1;
          }
    defined.swap(next);
  }
}

}  // namespace

template <typename Scalar>
NodeDisplacement node_displacement(const Level<3, Scalar>& level,
                                   const std::function<double(int, std::ptrdiff_t)>& value) {
  const auto& lat = level.lattice;
  NodeDisplacement u;
  u.nodes = lat.cells + IVec<3>::Ones();
  u.h = lat.h;
  u.origin = lat.origin;
  u.values.assign(3 * std::size_t(u.nodes.prod()), 0.0);
  std::vector<char> defined_node(u.values.size(), 0);
  // Node (i, j, k) is the lower corner of stored cell (i+1, j+1, k+1); the faces normal to e_a
  // sharing it are the lower a-faces of that cell and of its neighbors across the other axes.
  // Each node is written once from reads alone (`value` must be safe to call concurrently).
#pragma omp parallel for schedule(static)
  for (int k = 0; k < u.nodes[2]; ++k)
    for (int j = 0; j < u.nodes[1]; ++j)
      for (int i = 0; i < u.nodes[0]; ++i) {
        const std::ptrdiff_t corner = lat.index(IVec<3>(i + 1, j + 1, k + 1));
        const std::size_t n = (std::size_t(k) * u.nodes[1] + j) * u.nodes[0] + i;
        for (int a = 0; a < 3; ++a) {
          const int b = (a + 1) % 3, c = (a + 2) % 3;
          // Faces at offsets (+-h/2, +-h/2) around the node: the mean of all four, or of a
          // diagonal pair, is exact for affine fields; otherwise take what is defined.
          std::array<double, 4> v{};
          std::array<bool, 4> defined{};
          for (int q = 0; q < 4; ++q) {
            const std::ptrdiff_t face = corner - (q & 1) * lat.stride(b) - (q >> 1) * lat.stride(c);
            defined[q] = level.kind(a, face) != VarKind::INACTIVE;
            if (defined[q]) v[q] = value(a, face);
          }
          double sum = 0;
          int count = 0;
          if (!(defined[0] && defined[1] && defined[2] && defined[3])) {
            for (auto [p, q] : {std::pair{0, 3}, std::pair{1, 2}}) {
              if (count == 0 && defined[p] && defined[q]) {
                sum = v[p] + v[q];
                count = 2;
              }
            }
          }
          if (count == 0) {
            for (int q = 0; q < 4; ++q) {
              if (!defined[q]) continue;
              sum += v[q];
              ++count;
            }
          }
          u.values[3 * n + a] = count ? sum / count : 0.0;
          defined_node[3 * n + a] = count > 0;
        }
      }
  extend_into_empty_nodes(u, defined_node, 2);
  return u;
}

std::vector<double> von_mises_stress(const NodeDisplacement& u, const Material& material) {
  const IVec<3> cells = u.nodes - IVec<3>::Ones();
  std::vector<double> result(std::size_t(cells.prod()));
  const double mu = material.mu(), lambda = material.lambda();
#pragma omp parallel for schedule(static)
  for (int k = 0; k < cells[2]; ++k)
    for (int j = 0; j < cells[1]; ++j)
      for (int i = 0; i < cells[0]; ++i) {
        // Gradient at the cell center: average of the four edge differences along each axis.
        Eigen::Matrix3d grad = Eigen::Matrix3d::Zero();
        for (int c = 0; c < 8; ++c) {
          const int dx = c & 1, dy = (c >> 1) & 1, dz = (c >> 2) & 1;
          const Vec<3> v = u.at(i + dx, j + dy, k + dz);
          const Vec<3> sign((dx ? 1 : -1), (dy ? 1 : -1), (dz ? 1 : -1));
          grad += v * sign.transpose() / (4.0 * u.h);
        }
        const Eigen::Matrix3d strain = 0.5 * (grad + grad.transpose());
        const Eigen::Matrix3d stress =
            2 * mu * strain + lambda * strain.trace() * Eigen::Matrix3d::Identity();
        const Eigen::Matrix3d deviator =
            stress - stress.trace() / 3.0 * Eigen::Matrix3d::Identity();
        result[(std::size_t(k) * cells[1] + j) * cells[0] + i] =
            std::sqrt(1.5 * deviator.cwiseProduct(deviator).sum());
      }
  return result;
}

template NodeDisplacement node_displacement<float>(
    const Level<3, float>&, const std::function<double(int, std::ptrdiff_t)>&);
template NodeDisplacement node_displacement<double>(
    const Level<3, double>&, const std::function<double(int, std::ptrdiff_t)>&);

}  // namespace mgelastic::grid
