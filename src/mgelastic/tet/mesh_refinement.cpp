#include "mgelastic/tet/mesh_refinement.hpp"

#include <algorithm>
#include <array>
#include <unordered_map>
#include <vector>

namespace mgelastic::tet {

geometry::TetMesh refine_uniform(const geometry::TetMesh& mesh) {
  const int n = mesh.vertex_count();
  std::unordered_map<long long, int> midpoint_of_edge;
  midpoint_of_edge.reserve(static_cast<std::size_t>(mesh.tet_count()) * 2);
  std::vector<Eigen::Vector3d> added;
  const auto midpoint = [&](int a, int b) {
    const long long key = static_cast<long long>(std::min(a, b)) * n + std::max(a, b);
    const auto [it, inserted] =
        midpoint_of_edge.try_emplace(key, n + static_cast<int>(added.size()));
    if (inserted) added.push_back(0.5 * (mesh.vertices.row(a) + mesh.vertices.row(b)).transpose());
    return it->second;
  };
  std::vector<std::array<int, 4>> children;
  children.reserve(8 * static_cast<std::size_t>(mesh.tet_count()));
  for (int t = 0; t < mesh.tet_count(); ++t) {
    const int v0 = mesh.tets(t, 0), v1 = mesh.tets(t, 1), v2 = mesh.tets(t, 2),
              v3 = mesh.tets(t, 3);
    const int m01 = midpoint(v0, v1), m02 = midpoint(v0, v2), m03 = midpoint(v0, v3),
              m12 = midpoint(v1, v2), m13 = midpoint(v1, v3), m23 = midpoint(v2, v3);
    children.push_back({v0, m01, m02, m03});
    children.push_back({m01, v1, m12, m13});
    children.push_back({m02, m12, v2, m23});
    children.push_back({m03, m13, m23, v3});
    // Inner octahedron: opposite midpoint pairs; split along the shortest diagonal (p, q), the
    // other four midpoints form the ring a, b, a', b' around it.
    const std::array<std::array<int, 2>, 3> pairs{{{m01, m23}, {m02, m13}, {m03, m12}}};
    const auto position = [&](int v) -> Eigen::Vector3d {
      return v < n ? Eigen::Vector3d(mesh.vertices.row(v).transpose()) : added[v - n];
    };
    int d = 0;
    double shortest = (position(pairs[0][0]) - position(pairs[0][1])).squaredNorm();
    for (int c = 1; c < 3; ++c) {
      const double length = (position(pairs[c][0]) - position(pairs[c][1])).squaredNorm();
      if (length < shortest) {
        shortest = length;
        d = c;
      }
    }
    const std::array<int, 2>& a = pairs[(d + 1) % 3];
    const std::array<int, 2>& b = pairs[(d + 2) % 3];
    const std::array<int, 4> ring{a[0], b[0], a[1], b[1]};
    for (int r = 0; r < 4; ++r)
      children.push_back({pairs[d][0], pairs[d][1], ring[r], ring[(r + 1) % 4]});
  }
  geometry::TetMesh refined;
  refined.vertices.resize(n + static_cast<Eigen::Index>(added.size()), 3);
  refined.vertices.topRows(n) = mesh.vertices;
  for (std::size_t i = 0; i < added.size(); ++i)
    refined.vertices.row(n + static_cast<Eigen::Index>(i)) = added[i].transpose();
  refined.tets.resize(static_cast<Eigen::Index>(children.size()), 4);
  for (std::size_t c = 0; c < children.size(); ++c) {
    std::array<int, 4> tet = children[c];
    const auto p = [&](int s) -> Eigen::Vector3d {
      return refined.vertices.row(tet[s]).transpose();
    };
    if (geometry::signed_volume6(p(0), p(1), p(2), p(3)) < 0.0) std::swap(tet[2], tet[3]);
    for (int s = 0; s < 4; ++s) refined.tets(static_cast<Eigen::Index>(c), s) = tet[s];
  }
  if (mesh.element_tags.size() == mesh.tet_count()) {
    refined.element_tags.resize(8 * static_cast<Eigen::Index>(mesh.tet_count()));
    for (int t = 0; t < mesh.tet_count(); ++t)
      refined.element_tags.segment<8>(8 * static_cast<Eigen::Index>(t))
          .setConstant(mesh.element_tags[t]);
  }
  return refined;
}

}  // namespace mgelastic::tet
