// STL reader, ASCII and binary. STL stores every triangle's corners by value, so corners with
// identical coordinates are welded into shared vertices (exact comparison: exporters write the
// same bits for a shared corner, and near-coincident corners may be genuinely distinct).
#include <array>
#include <cctype>
#include <fstream>
#include <sstream>
#include <unordered_map>

#include "mgelastic/geometry/surface_mesh_builder.hpp"
#include "mgelastic/geometry/surface_mesh_readers.hpp"

namespace mgelastic::geometry {
namespace {

using detail::SurfaceMeshBuilder;
using detail::TextCursor;

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open file", ErrorContext{.file = path.string()});
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return std::move(buffer).str();
}

struct CornerHash {
  std::size_t operator()(const std::array<double, 3>& x) const {
    std::size_t h = 0;
    for (const double c : x) h = h * 1000003u ^ std::hash<double>()(c);
    return h;
  }
};

// Welds corners with identical coordinates into one vertex.
class CornerWelder {
 public:
  explicit CornerWelder(SurfaceMeshBuilder& builder) : m_builder(builder) {}
  long vertex(double x, double y, double z) {
    // +0.0 turns -0.0 into 0.0, which compares equal but hashes differently.
    const std::array<double, 3> key{x + 0.0, y + 0.0, z + 0.0};
    const auto [it, inserted] = m_ids.try_emplace(key, m_builder.vertex_count());
    if (inserted) m_builder.add_vertex(x, y, z);
    return it->second;
  }

 private:
  SurfaceMeshBuilder& m_builder;
  std::unordered_map<std::array<double, 3>, long, CornerHash> m_ids;
};

std::uint32_t announced_triangles(const std::string& data) {
  std::uint32_t n = 0;
  for (int b = 3; b >= 0; --b) n = n << 8 | static_cast<unsigned char>(data[80 + b]);
  return n;
}

bool is_binary(const std::string& data) {
  return data.size() >= 84 && data.size() == 84 + 50 * std::uint64_t{announced_triangles(data)};
}

// ASCII STL is printable text starting with "solid"; a binary file whose size does not match its
// header (truncated) fails this test and is reported as such.
bool looks_ascii(const std::string& data) {
  std::size_t start = 0;
  while (start < data.size() && std::isspace(static_cast<unsigned char>(data[start]))) ++start;
  if (data.compare(start, 5, "solid") != 0) return false;
  const std::size_t probe = std::min<std::size_t>(data.size(), 4096);
  for (std::size_t i = 0; i < probe; ++i) {
    const auto c = static_cast<unsigned char>(data[i]);
    if (c >= 127 || (c < 32 && !std::isspace(c))) return false;
  }
  return true;
}

TriangleMesh read_binary(TextCursor& cursor, std::uint32_t n) {
  SurfaceMeshBuilder builder(cursor, true);
  builder.reserve(n / 2, n);
  CornerWelder welder(builder);
  char header[80];
  cursor.read_bytes(header, sizeof header, "header");
  detail::read_binary_value<std::uint32_t>(cursor, false, "triangle count");
  std::array<long, 3> corners;
  for (std::uint32_t t = 0; t < n; ++t) {
    for (int k = 0; k < 3; ++k) detail::read_binary_value<float>(cursor, false, "normal");
    for (long& corner : corners) {
      float x[3];
      for (float& c : x) c = detail::read_binary_value<float>(cursor, false, "vertex");
      corner = welder.vertex(x[0], x[1], x[2]);
    }
    detail::read_binary_value<std::uint16_t>(cursor, false, "attribute");
    builder.add_polygon(corners, builder.vertex_count(), 0);
  }
  return builder.finish();
}

void read_ascii_vertex(TextCursor& cursor, CornerWelder& welder, std::vector<long>& loop) {
  double x[3];
  for (double& c : x) c = detail::parse_coordinate(cursor.expect_token("vertex"), cursor);
  loop.push_back(welder.vertex(x[0], x[1], x[2]));
}

TriangleMesh read_ascii(TextCursor& cursor) {
  SurfaceMeshBuilder builder(cursor, false);
  CornerWelder welder(builder);
  std::vector<long> loop;
  std::string_view token;
  while (cursor.next_token(token)) {
    if (token == "solid" || token == "endsolid") {
      cursor.skip_rest_of_line();  // the solid's name
    } else if (token == "facet") {
      if (cursor.expect_token("facet") != "normal") throw cursor.error("expected 'facet normal'");
      for (int k = 0; k < 3; ++k) detail::parse_coordinate(cursor.expect_token("normal"), cursor);
    } else if (token == "outer") {
      if (cursor.expect_token("outer") != "loop") throw cursor.error("expected 'outer loop'");
      loop.clear();
    } else if (token == "vertex") {
      read_ascii_vertex(cursor, welder, loop);
    } else if (token == "endloop") {
      builder.add_polygon(loop, builder.vertex_count(), 0);
    } else if (token != "endfacet") {
      throw cursor.error("unexpected '" + std::string(token) + "' in ASCII STL");
    }
  }
  return builder.finish();
}

}  // namespace

TriangleMesh read_stl(const std::filesystem::path& path) {
  std::string data = read_file(path);
  const bool binary = is_binary(data);
  const bool ascii = !binary && looks_ascii(data);
  const std::uint32_t n = data.size() >= 84 ? announced_triangles(data) : 0;
  const std::size_t size = data.size();
  TextCursor cursor(std::move(data), path.string());
  if (binary) return read_binary(cursor, n);
  if (ascii) return read_ascii(cursor);
  throw Error("neither ASCII STL (no leading 'solid') nor binary STL: the file has " +
                  std::to_string(size) + " bytes, a binary STL announcing " + std::to_string(n) +
                  " triangles has 84 + 50 * " + std::to_string(n) + " = " +
                  std::to_string(84 + 50 * std::uint64_t{n}) + " (truncated or corrupt file?)",
              ErrorContext{path.string(), -1, "byte 80"});
}

}  // namespace mgelastic::geometry
