// TetGen .node/.ele reader (see tet_mesh_readers.hpp for the conventions).
#include <vector>

#include "mgelastic/geometry/tet_mesh_readers.hpp"
#include "mgelastic/geometry/tet_mesh_text.hpp"

namespace mgelastic::geometry {

namespace {

using detail::parse_double;
using detail::parse_int;
using detail::TextCursor;
using Record = std::vector<std::string_view>;

Record header(TextCursor& cursor, std::size_t minimum, const std::string& what) {
  Record tokens;
  if (!cursor.next_record(tokens)) throw cursor.error("empty file: missing " + what + " header");
  if (tokens.size() < minimum)
    throw cursor.error(what + " header needs " + std::to_string(minimum) + " numbers");
  return tokens;
}

void expect_end(TextCursor& cursor, long declared, const std::string& what) {
  Record tokens;
  if (cursor.next_record(tokens))
    throw cursor.error("more " + what + " than the " + std::to_string(declared) +
                       " declared in the header (wrong count?)");
}

// Reads the .node file; returns the first index (TetGen's index base).
long read_nodes(TextCursor& cursor, TetMesh& mesh) {
  const Record head = header(cursor, 2, "node");
  const long count = parse_int(head[0], cursor, "node count");
  const long dimension = parse_int(head[1], cursor, "dimension");
  const long attributes = head.size() > 2 ? parse_int(head[2], cursor, "attribute count") : 0;
  const long markers = head.size() > 3 ? parse_int(head[3], cursor, "boundary marker flag") : 0;
  if (count <= 0 || dimension != 3 || attributes < 0 || markers < 0 || markers > 1)
    throw cursor.error("invalid node header (need count > 0, dimension 3)");
  cursor.require_room(attributes, 2, "attributes per node");
  const long values = 4 + attributes + markers;
  cursor.require_room(count, 2 * values, "nodes");
  mesh.vertices.resize(count, 3);
  long base = 0;
  Record tokens;
  for (long i = 0; i < count; ++i) {
    if (!cursor.next_record(tokens))
      throw cursor.error("unexpected end of file (truncated?): read " + std::to_string(i) + " of " +
                         std::to_string(count) + " nodes");
    if (static_cast<long>(tokens.size()) != values)
      throw cursor.error("node line has " + std::to_string(tokens.size()) + " values, expected " +
                         std::to_string(values));
    const long index = parse_int(tokens[0], cursor, "node index");
    if (i == 0) base = index;
    if (index != base + i || (base != 0 && base != 1))
      throw cursor.error("node index " + std::to_string(index) + " out of sequence");
    for (int k = 0; k < 3; ++k) mesh.vertices(i, k) = parse_double(tokens[1 + k], cursor, "x");
  }
  expect_end(cursor, count, "nodes");
  return base;
}

void read_elements(TextCursor& cursor, long base, TetMesh& mesh, std::vector<long>& lines) {
  const Record head = header(cursor, 2, "element");
  const long count = parse_int(head[0], cursor, "element count");
  const long nodes = parse_int(head[1], cursor, "nodes per tetrahedron");
  const long attributes = head.size() > 2 ? parse_int(head[2], cursor, "attribute count") : 0;
  if (count <= 0 || (nodes != 4 && nodes != 10) || attributes < 0)
    throw cursor.error("invalid element header (need count > 0, 4 or 10 nodes per tetrahedron)");
  cursor.require_room(attributes, 2, "attributes per tetrahedron");
  const long values = 1 + nodes + attributes;
  cursor.require_room(count, 2 * values, "tetrahedra");
  mesh.tets.resize(count, 4);
  lines.resize(count);
  Record tokens;
  for (long e = 0; e < count; ++e) {
    if (!cursor.next_record(tokens))
      throw cursor.error("unexpected end of file (truncated?): read " + std::to_string(e) + " of " +
                         std::to_string(count) + " tetrahedra");
    if (static_cast<long>(tokens.size()) != values)
      throw cursor.error("element line has " + std::to_string(tokens.size()) +
                         " values, expected " + std::to_string(values));
    lines[e] = cursor.line();
    for (int a = 0; a < 4; ++a) {
      // Compared before subtracting the base: the file may hold any long, LONG_MIN included.
      const long index = parse_int(tokens[1 + a], cursor, "vertex index");
      if (index < base || index - base >= mesh.vertex_count())
        throw cursor.error("vertex index " + std::string(tokens[1 + a]) + " out of range");
      mesh.tets(e, a) = static_cast<int>(index - base);
    }
  }
  expect_end(cursor, count, "elements");
}

}  // namespace

TetMesh read_tetgen(const std::filesystem::path& path, const TetMeshReadOptions& options) {
  std::filesystem::path base = path;
  if (base.extension() == ".node" || base.extension() == ".ele") base.replace_extension();
  TextCursor nodes(std::filesystem::path(base.string() + ".node"));
  TextCursor elements(std::filesystem::path(base.string() + ".ele"));
  TetMesh mesh;
  const long index_base = read_nodes(nodes, mesh);
  std::vector<long> lines;
  read_elements(elements, index_base, mesh, lines);
  check_tet_mesh(mesh, options, elements.source(), lines);
  return mesh;
}

}  // namespace mgelastic::geometry
