// MEDIT .mesh reader (ASCII): keyword sections, 1-based indices, a reference after each entity.
#include <map>
#include <string>

#include "mgelastic/geometry/tet_mesh_readers.hpp"
#include "mgelastic/geometry/tet_mesh_text.hpp"

namespace mgelastic::geometry {

namespace {

using detail::TextCursor;

// Numbers per entity of the sections we skip, so an unread section cannot desynchronize parsing.
const std::map<std::string, int>& skipped_section_widths() {
  static const std::map<std::string, int> widths = {{"Edges", 3},
                                                    {"Triangles", 4},
                                                    {"Quadrilaterals", 5},
                                                    {"Hexahedra", 9},
                                                    {"Prisms", 7},
                                                    {"Pyramids", 6},
                                                    {"Corners", 1},
                                                    {"Ridges", 1},
                                                    {"RequiredVertices", 1},
                                                    {"RequiredEdges", 1},
                                                    {"RequiredTriangles", 1},
                                                    {"Normals", 3},
                                                    {"Tangents", 3},
                                                    {"NormalAtVertices", 2},
                                                    {"TangentAtVertices", 2}};
  return widths;
}

// The entity count of a section whose entities have `width` numbers each.
long section_count(TextCursor& cursor, const std::string& section, int width) {
  const long count = cursor.expect_int(section + " count");
  if (count < 0) throw cursor.error("negative " + section + " count");
  cursor.require_room(count, 2 * width, section);
  return count;
}

void read_vertices(TextCursor& cursor, TetMesh& mesh) {
  const long count = section_count(cursor, "Vertices", 4);
  mesh.vertices.resize(count, 3);
  for (long v = 0; v < count; ++v) {
    for (int k = 0; k < 3; ++k) mesh.vertices(v, k) = cursor.expect_double("vertex coordinate");
    cursor.expect_int("vertex reference");
  }
}

void read_tetrahedra(TextCursor& cursor, TetMesh& mesh, std::vector<long>& lines) {
  const long count = section_count(cursor, "Tetrahedra", 5);
  mesh.tets.resize(count, 4);
  mesh.element_tags.resize(count);
  lines.resize(count);
  for (long t = 0; t < count; ++t) {
    for (int a = 0; a < 4; ++a) {
      const long index = cursor.expect_int("tetrahedron vertex");  // 1-based
      if (a == 0) lines[t] = cursor.line();
      if (index < 1 || index > mesh.vertex_count())
        throw cursor.error("vertex index " + std::to_string(index) + " out of range [1, " +
                           std::to_string(mesh.vertex_count()) +
                           "] (or Tetrahedra before Vertices)");
      mesh.tets(t, a) = static_cast<int>(index - 1);
    }
    mesh.element_tags(t) = static_cast<int>(cursor.expect_int("tetrahedron reference"));
  }
}

void skip_section(TextCursor& cursor, const std::string& keyword, int width) {
  const long count = section_count(cursor, keyword, width);
  for (long i = 0; i < count * width; ++i) cursor.expect_token(keyword + " entry");
}

}  // namespace

TetMesh read_medit(const std::filesystem::path& path, const TetMeshReadOptions& options) {
  TextCursor cursor(path);
  TetMesh mesh;
  std::vector<long> lines;
  bool have_vertices = false;
  std::string_view token;
  while (cursor.next_token(token)) {
    const std::string keyword(token);
    if (keyword == "End") break;
    if (keyword[0] == '#') {  // comment line
      cursor.skip_rest_of_line();
    } else if (keyword == "MeshVersionFormatted") {
      cursor.expect_int("mesh version");
    } else if (keyword == "Dimension") {
      if (cursor.expect_int("dimension") != 3) throw cursor.error("only Dimension 3 is supported");
    } else if (keyword == "Vertices") {
      read_vertices(cursor, mesh);
      have_vertices = true;
    } else if (keyword == "Tetrahedra") {
      read_tetrahedra(cursor, mesh, lines);
    } else if (skipped_section_widths().count(keyword) != 0) {
      skip_section(cursor, keyword, skipped_section_widths().at(keyword));
    } else {
      throw cursor.error("unknown MEDIT keyword '" + keyword + "'");
    }
  }
  if (!have_vertices) throw cursor.error("no Vertices section");
  if (mesh.tets.rows() == 0) throw cursor.error("no Tetrahedra section");
  check_tet_mesh(mesh, options, cursor.source(), lines);
  return mesh;
}

}  // namespace mgelastic::geometry
