#include "mgelastic/geometry/tet_mesh_boundary.hpp"

#include <algorithm>
#include <array>
#include <map>

namespace mgelastic::geometry {

TetMeshBoundary tet_mesh_boundary(const TetMesh& mesh) {
  // For a positively oriented tet (v0..v3) these faces have right-hand normals pointing away
  // from the opposite vertex.
  static constexpr std::array<std::array<int, 3>, 4> kFaces = {
      {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}}};
  std::map<std::array<int, 3>, std::pair<int, std::array<int, 3>>> faces;  // sorted -> count, face
  for (int t = 0; t < mesh.tet_count(); ++t)
    for (const auto& f : kFaces) {
      const std::array<int, 3> face{mesh.tets(t, f[0]), mesh.tets(t, f[1]), mesh.tets(t, f[2])};
      std::array<int, 3> key = face;
      std::sort(key.begin(), key.end());
      auto [it, inserted] = faces.try_emplace(key, 0, face);
      ++it->second.first;
    }
  TetMeshBoundary surface;
  std::vector<int> surface_vertex(mesh.vertex_count(), -1);
  std::vector<std::array<int, 3>> triangles;
  for (const auto& [key, entry] : faces) {
    if (entry.first != 1) continue;
    std::array<int, 3> triangle;
    for (int k = 0; k < 3; ++k) {
      int& id = surface_vertex[entry.second[k]];
      if (id < 0) {
        id = static_cast<int>(surface.mesh_vertex.size());
        surface.mesh_vertex.push_back(entry.second[k]);
      }
      triangle[k] = id;
    }
    triangles.push_back(triangle);
  }
  surface.triangles.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k)
      surface.triangles(static_cast<Eigen::Index>(t), k) = triangles[t][k];
  return surface;
}

}  // namespace mgelastic::geometry
