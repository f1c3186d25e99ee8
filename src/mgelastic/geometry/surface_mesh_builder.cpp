#include "mgelastic/geometry/surface_mesh_builder.hpp"

#include <cmath>

namespace mgelastic::geometry::detail {

void SurfaceMeshBuilder::reserve(long vertices, long triangles) {
  // Counts come from file headers: cap them so a corrupt header cannot demand terabytes (every
  // vertex and triangle takes at least a byte of the file).
  const long cap = std::min(1L << 24, static_cast<long>(m_cursor.remaining()));
  m_vertices.reserve(3 * std::min(std::max(vertices, 0L), cap));
  m_triangles.reserve(3 * std::min(std::max(triangles, 0L), cap));
}

void SurfaceMeshBuilder::add_vertex(double x, double y, double z) {
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
    throw error("vertex " + std::to_string(vertex_count()) + " has a NaN or infinite coordinate");
  m_vertices.insert(m_vertices.end(), {x, y, z});
}

void SurfaceMeshBuilder::add_polygon(std::span<const long> corners, long limit, int base) {
  const std::string face = "face " + std::to_string(m_faces);
  if (corners.size() < 3)
    throw error(face + " has " + std::to_string(corners.size()) + " vertices (at least 3 needed)");
  for (const long v : corners)
    if (v < 0 || v >= limit)
      throw error(face + ": vertex index " + std::to_string(v + base) + " out of range [" +
                  std::to_string(base) + ", " + std::to_string(limit - 1 + base) + "]");
  // Fan from the first corner: exact for the convex polygons exporters write.
  for (std::size_t k = 1; k + 1 < corners.size(); ++k)
    m_triangles.insert(m_triangles.end(),
                       {static_cast<int>(corners[0]), static_cast<int>(corners[k]),
                        static_cast<int>(corners[k + 1])});
  ++m_faces;
}

TriangleMesh SurfaceMeshBuilder::finish() const {
  if (m_triangles.empty())
    throw error("no triangles (" + std::to_string(vertex_count()) + " vertices, " +
                std::to_string(m_faces) + " faces)");
  TriangleMesh mesh;
  mesh.vertices = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(
      m_vertices.data(), vertex_count(), 3);
  mesh.triangles = Eigen::Map<const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>>(
      m_triangles.data(), static_cast<Eigen::Index>(m_triangles.size() / 3), 3);
  return mesh;
}

Error SurfaceMeshBuilder::error(const std::string& reason) const {
  return m_binary ? m_cursor.binary_error(reason) : m_cursor.error(reason);
}

double parse_coordinate(std::string_view token, const TextCursor& cursor) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  return parse_double(token, cursor, "coordinate");
}

}  // namespace mgelastic::geometry::detail
