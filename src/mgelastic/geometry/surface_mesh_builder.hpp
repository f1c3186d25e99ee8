#pragma once
// Internal helper of the surface mesh readers: collects vertices and polygons, fan-triangulates,
// and checks what each reader would otherwise check alike (finite coordinates, indices in range,
// a non-empty result). Errors go through the reader's cursor, so they name the file and the line
// (text) or the byte offset (binary data).
#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <vector>

#include "mgelastic/geometry/tet_mesh_text.hpp"
#include "mgelastic/geometry/triangle_mesh.hpp"

namespace mgelastic::geometry::detail {

class SurfaceMeshBuilder {
 public:
  // `binary`: errors name the cursor's byte offset instead of its line.
  SurfaceMeshBuilder(const TextCursor& cursor, bool binary) : m_cursor(cursor), m_binary(binary) {}

  long vertex_count() const { return static_cast<long>(m_vertices.size() / 3); }
  long face_count() const { return m_faces; }
  void reserve(long vertices, long triangles);

  // Appends a vertex; Error on NaN or infinite coordinates.
  void add_vertex(double x, double y, double z);
  // Appends a polygon of 0-based indices into the first `limit` vertices, fan-triangulated.
  // Messages quote indices as index + `base`, the way the file writes them.
  void add_polygon(std::span<const long> corners, long limit, int base);
  // The mesh; Error when it has no triangles.
  TriangleMesh finish() const;

  Error error(const std::string& reason) const;

 private:
  const TextCursor& m_cursor;
  bool m_binary;
  long m_faces = 0;
  std::vector<double> m_vertices;
  std::vector<int> m_triangles;
};

// Numbers as OBJ/OFF/STL writers spell them (from_chars rejects a leading '+').
double parse_coordinate(std::string_view token, const TextCursor& cursor);

// A binary value of type T stored with the given byte order.
template <class T>
T read_binary_value(TextCursor& cursor, bool big_endian, const std::string& what) {
  unsigned char bytes[sizeof(T)];
  cursor.read_bytes(bytes, sizeof(T), what);
  if (big_endian != (std::endian::native == std::endian::big))
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(bytes[i], bytes[sizeof(T) - 1 - i]);
  T value;
  std::memcpy(&value, bytes, sizeof(T));
  return value;
}

}  // namespace mgelastic::geometry::detail
