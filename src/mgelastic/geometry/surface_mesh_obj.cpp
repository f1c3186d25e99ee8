// Wavefront OBJ reader: line records, 1-based or negative (relative) indices.
#include <set>
#include <string>
#include <vector>

#include "mgelastic/geometry/surface_mesh_builder.hpp"
#include "mgelastic/geometry/surface_mesh_readers.hpp"

namespace mgelastic::geometry {
namespace {

using detail::SurfaceMeshBuilder;
using detail::TextCursor;

// OBJ statements that carry nothing a solid needs; anything else is an error, so a file of
// another format or a corrupt one is not silently read as an empty mesh.
bool is_ignored_statement(std::string_view keyword) {
  static const std::set<std::string_view> ignored = {
      "vt",    "vn",     "vp",     "g",        "o",        "s",          "usemtl",    "mtllib",
      "l",     "p",      "mg",     "cstype",   "deg",      "bmat",       "step",      "curv",
      "curv2", "surf",   "parm",   "trim",     "hole",     "scrv",       "sp",        "end",
      "con",   "lod",    "bevel",  "c_interp", "d_interp", "shadow_obj", "trace_obj", "ctech",
      "stech", "maplib", "usemap", "call",     "csh"};
  return ignored.count(keyword) != 0;
}

// The vertex part of a corner "i", "i/t", "i//n" or "i/t/n", made 0-based.
long corner_index(std::string_view token, const TextCursor& cursor, long vertex_count, long face) {
  const long i = detail::parse_int(token.substr(0, token.find('/')), cursor, "face vertex index");
  if (i == 0)
    throw cursor.error("face " + std::to_string(face) +
                       ": vertex index 0 (OBJ indices start at 1)");
  if (i < -vertex_count)
    throw cursor.error("face " + std::to_string(face) + ": relative vertex index " +
                       std::to_string(i) + " out of range (" + std::to_string(vertex_count) +
                       " vertices so far)");
  return i > 0 ? i - 1 : vertex_count + i;
}

void read_vertex(const std::vector<std::string_view>& tokens, const TextCursor& cursor,
                 SurfaceMeshBuilder& builder) {
  if (tokens.size() < 4) throw cursor.error("vertex needs 3 coordinates");
  builder.add_vertex(detail::parse_coordinate(tokens[1], cursor),
                     detail::parse_coordinate(tokens[2], cursor),
                     detail::parse_coordinate(tokens[3], cursor));
}

void read_face(const std::vector<std::string_view>& tokens, const TextCursor& cursor,
               SurfaceMeshBuilder& builder, std::vector<long>& corners) {
  corners.clear();
  for (std::size_t k = 1; k < tokens.size(); ++k)
    corners.push_back(
        corner_index(tokens[k], cursor, builder.vertex_count(), builder.face_count()));
  builder.add_polygon(corners, builder.vertex_count(), 1);
}

}  // namespace

TriangleMesh read_obj(const std::filesystem::path& path) {
  TextCursor cursor(path);
  SurfaceMeshBuilder builder(cursor, false);
  std::vector<std::string_view> tokens;
  std::vector<long> corners;
  while (cursor.next_record(tokens)) {
    if (tokens[0] == "v") {
      read_vertex(tokens, cursor, builder);
    } else if (tokens[0] == "f" || tokens[0] == "fo") {
      read_face(tokens, cursor, builder, corners);
    } else if (!is_ignored_statement(tokens[0])) {
      throw cursor.error("unknown OBJ statement '" + std::string(tokens[0]) + "'");
    }
  }
  return builder.finish();
}

}  // namespace mgelastic::geometry
