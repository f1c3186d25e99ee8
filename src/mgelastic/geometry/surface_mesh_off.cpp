// Object File Format reader: "OFF" header (optionally with the counts on the same line), counts
// line "nv nf ne", nv vertex lines, nf face lines "n i1 ... in [colour]", 0-based indices,
// '#' comments.
#include <set>
#include <string>
#include <vector>

#include "mgelastic/geometry/surface_mesh_builder.hpp"
#include "mgelastic/geometry/surface_mesh_readers.hpp"

namespace mgelastic::geometry {
namespace {

using detail::SurfaceMeshBuilder;
using detail::TextCursor;

struct OffCounts {
  long vertices = 0;
  long faces = 0;
};

// The header keyword, then the counts (on the same line or the next record).
OffCounts read_counts(TextCursor& cursor) {
  // Colour and normal variants keep x y z first, so reading the first three numbers is enough.
  static const std::set<std::string_view> variants = {"OFF", "COFF", "NOFF", "CNOFF"};
  std::vector<std::string_view> tokens;
  if (!cursor.next_record(tokens)) throw cursor.error("empty file");
  if (variants.count(tokens[0]) == 0)
    throw cursor.error("not an OFF file (header '" + std::string(tokens[0]) +
                       "'; supported: OFF, COFF, NOFF, CNOFF in ASCII)");
  if (tokens.size() == 1 && !cursor.next_record(tokens)) throw cursor.error("missing counts");
  const std::size_t first = variants.count(tokens[0]) != 0 ? 1 : 0;
  if (tokens.size() < first + 2) throw cursor.error("expected counts 'vertices faces edges'");
  OffCounts counts{detail::parse_int(tokens[first], cursor, "vertex count"),
                   detail::parse_int(tokens[first + 1], cursor, "face count")};
  if (counts.vertices < 0 || counts.faces < 0) throw cursor.error("negative count");
  return counts;
}

void read_vertices(TextCursor& cursor, long count, SurfaceMeshBuilder& builder) {
  std::vector<std::string_view> tokens;
  for (long v = 0; v < count; ++v) {
    if (!cursor.next_record(tokens))
      throw cursor.error("unexpected end of file after " + std::to_string(v) + " of " +
                         std::to_string(count) + " vertices");
    if (tokens.size() < 3) throw cursor.error("vertex " + std::to_string(v) + " needs 3 numbers");
    builder.add_vertex(detail::parse_coordinate(tokens[0], cursor),
                       detail::parse_coordinate(tokens[1], cursor),
                       detail::parse_coordinate(tokens[2], cursor));
  }
}

void read_faces(TextCursor& cursor, long count, long vertex_count, SurfaceMeshBuilder& builder) {
  std::vector<std::string_view> tokens;
  std::vector<long> corners;
  for (long f = 0; f < count; ++f) {
    if (!cursor.next_record(tokens))
      throw cursor.error("unexpected end of file after " + std::to_string(f) + " of " +
                         std::to_string(count) + " faces");
    const long n = detail::parse_int(tokens[0], cursor, "face size");
    if (n < 0 || static_cast<std::size_t>(n) + 1 > tokens.size())
      throw cursor.error("face " + std::to_string(f) + " announces " + std::to_string(n) +
                         " vertices but lists " + std::to_string(tokens.size() - 1));
    corners.clear();
    for (long k = 1; k <= n; ++k)
      corners.push_back(detail::parse_int(tokens[k], cursor, "face vertex index"));
    builder.add_polygon(corners, vertex_count, 0);
  }
}

}  // namespace

TriangleMesh read_off(const std::filesystem::path& path) {
  TextCursor cursor(path);
  const OffCounts counts = read_counts(cursor);
  SurfaceMeshBuilder builder(cursor, false);
  builder.reserve(counts.vertices, counts.faces);
  read_vertices(cursor, counts.vertices, builder);
  read_faces(cursor, counts.faces, counts.vertices, builder);
  std::vector<std::string_view> tokens;
  if (cursor.next_record(tokens))
    throw cursor.error("data after the last of " + std::to_string(counts.faces) +
                       " faces (counts in the header do not match the data)");
  return builder.finish();
}

}  // namespace mgelastic::geometry
