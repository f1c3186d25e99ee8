// Gmsh .msh reader: versions 2.2 and 4.1, ASCII and binary (see tet_mesh_readers.hpp).
//
// Binary layout (little-endian machine assumed and checked by the "1" after the format line):
//  2.2  $Nodes: count (text), then per node int tag + 3 doubles.
//       $Elements: count (text), then blocks {int type, int n, int ntags} followed by n records
//       of int tag, ntags ints, nodes-per-type ints.
//  4.1  $Nodes: 4 size_t header, per entity block {int dim, int tag, int parametric, size_t n},
//       n size_t node tags, then n * (3 + dim * parametric) doubles.
//       $Elements: 4 size_t header, per block {int dim, int tag, int type, size_t n}, then n
//       records of size_t tag and nodes-per-type size_t node tags.
#include <array>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "mgelastic/geometry/tet_mesh_readers.hpp"
#include "mgelastic/geometry/tet_mesh_text.hpp"

namespace mgelastic::geometry {

namespace {

using detail::parse_double;
using detail::parse_int;
using detail::TextCursor;
using Record = std::vector<std::string_view>;

constexpr int kTetrahedron = 4;

// Nodes per Gmsh element type (0: unknown), needed to skip non-tetrahedra in binary files.
int nodes_per_type(long type) {
  static constexpr std::array<int, 32> table = {0,  2,  3,  4,  4, 8, 6,  5,  3,  6, 9,
                                                10, 27, 18, 14, 1, 8, 20, 15, 13, 9, 10,
                                                12, 15, 15, 21, 4, 5, 6,  20, 35, 56};
  if (type >= 0 && type < static_cast<long>(table.size())) return table[type];
  if (type == 92) return 64;
  if (type == 93) return 125;
  return 0;
}

struct GmshFormat {
  int major = 0;
  bool binary = false;
};

// Everything read so far; tets still hold Gmsh node tags until resolve().
struct GmshData {
  std::vector<Eigen::Vector3d> points;
  std::unordered_map<long, int> node_index;
  std::vector<std::array<long, 4>> tets;
  std::vector<int> tags;
  std::vector<long> lines;  // empty for binary data
};

void add_node(GmshData& data, long tag, const Eigen::Vector3d& p, const TextCursor& cursor) {
  if (!data.node_index.emplace(tag, static_cast<int>(data.points.size())).second)
    throw cursor.error("duplicate node tag " + std::to_string(tag));
  data.points.push_back(p);
}

void expect_keyword(TextCursor& cursor, const std::string& keyword, const std::string& hint) {
  const std::string_view token = cursor.expect_token(keyword);
  if (token != keyword)
    throw cursor.error("expected " + keyword + ", found '" + std::string(token) + "'" + hint);
}

GmshFormat read_format(TextCursor& cursor) {
  expect_keyword(cursor, "$MeshFormat", " (not a Gmsh file?)");
  const std::string version(cursor.expect_token("version"));
  const long file_type = cursor.expect_int("file type");
  const long data_size = cursor.expect_int("data size");
  GmshFormat format{.major = version.starts_with("2.") ? 2
                             : version == "4.1"        ? 4
                                                       : 0,
                    .binary = file_type == 1};
  if (format.major == 0)
    throw cursor.error("unsupported Gmsh version " + version + " (supported: 2.2, 4.1)");
  if (data_size != 8) throw cursor.error("unsupported data size " + std::to_string(data_size));
  if (format.binary) {
    cursor.skip_line_end();
    if (cursor.read_binary<int>("endianness marker") != 1)
      throw cursor.binary_error("binary Gmsh file with foreign byte order");
  }
  expect_keyword(cursor, "$EndMeshFormat", "");
  return format;
}

// ---- version 2.2 ----

void read_nodes_v2(TextCursor& cursor, bool binary, GmshData& data) {
  const long count = cursor.expect_int("node count");
  if (count <= 0) throw cursor.error("invalid node count");
  if (binary) cursor.skip_line_end();
  Record tokens;
  for (long i = 0; i < count; ++i) {
    if (binary) {
      const int tag = cursor.read_binary<int>("node tag");
      Eigen::Vector3d p;
      cursor.read_bytes(p.data(), 3 * sizeof(double), "node coordinates");
      add_node(data, tag, p, cursor);
      continue;
    }
    if (!cursor.next_record(tokens, false) || tokens[0] == "$EndNodes")
      throw cursor.error("read " + std::to_string(i) + " of " + std::to_string(count) +
                         " nodes (truncated file or wrong count?)");
    if (tokens.size() != 4) throw cursor.error("node line needs 4 values: tag x y z");
    const Eigen::Vector3d p(parse_double(tokens[1], cursor, "x"),
                            parse_double(tokens[2], cursor, "y"),
                            parse_double(tokens[3], cursor, "z"));
    add_node(data, parse_int(tokens[0], cursor, "node tag"), p, cursor);
  }
}

void read_elements_v2_ascii(TextCursor& cursor, long count, GmshData& data) {
  Record tokens;
  for (long i = 0; i < count; ++i) {
    if (!cursor.next_record(tokens, false) || tokens[0] == "$EndElements")
      throw cursor.error("read " + std::to_string(i) + " of " + std::to_string(count) +
                         " elements (truncated file or wrong count?)");
    if (tokens.size() < 3) throw cursor.error("element line needs tag, type, tag count");
    const long type = parse_int(tokens[1], cursor, "element type");
    const long ntags = parse_int(tokens[2], cursor, "tag count");
    if (type != kTetrahedron) continue;
    if (ntags < 0 || ntags > static_cast<long>(tokens.size()))
      throw cursor.error("invalid tag count " + std::to_string(ntags));
    if (static_cast<long>(tokens.size()) != 3 + ntags + 4)
      throw cursor.error("tetrahedron line needs " + std::to_string(3 + ntags + 4) + " values");
    std::array<long, 4> nodes;
    for (int a = 0; a < 4; ++a) nodes[a] = parse_int(tokens[3 + ntags + a], cursor, "node tag");
    data.tets.push_back(nodes);
    data.tags.push_back(ntags > 0 ? static_cast<int>(parse_int(tokens[3], cursor, "tag")) : 0);
    data.lines.push_back(cursor.line());
  }
}

void read_elements_v2_binary(TextCursor& cursor, long count, GmshData& data) {
  cursor.skip_line_end();
  long done = 0;
  while (done < count) {
    const int type = cursor.read_binary<int>("element block type");
    const int n = cursor.read_binary<int>("element block size");
    const int ntags = cursor.read_binary<int>("element tag count");
    const int nodes = nodes_per_type(type);
    if (nodes == 0 || n <= 0 || ntags < 0 || done + n > count)
      throw cursor.binary_error("invalid element block (type " + std::to_string(type) + ", size " +
                                std::to_string(n) + ")");
    cursor.require_room(ntags, sizeof(int), "element tags", true);
    std::vector<int> record(std::size_t{1} + ntags + nodes);
    for (int i = 0; i < n; ++i) {
      cursor.read_bytes(record.data(), record.size() * sizeof(int), "element record");
      if (type != kTetrahedron) continue;
      data.tets.push_back(
          {record[1 + ntags], record[2 + ntags], record[3 + ntags], record[4 + ntags]});
      data.tags.push_back(ntags > 0 ? record[1] : 0);
    }
    done += n;
  }
}

void read_elements_v2(TextCursor& cursor, bool binary, GmshData& data) {
  const long count = cursor.expect_int("element count");
  if (count < 0) throw cursor.error("invalid element count");
  if (binary) {
    read_elements_v2_binary(cursor, count, data);
  } else {
    read_elements_v2_ascii(cursor, count, data);
  }
}

// ---- version 4.1 ----

long read_size(TextCursor& cursor, bool binary, const std::string& what) {
  if (!binary) return cursor.expect_int(what);
  const auto value = cursor.read_binary<std::uint64_t>(what);
  if (value > (std::uint64_t{1} << 40)) throw cursor.binary_error("implausible " + what);
  return static_cast<long>(value);
}

int read_int(TextCursor& cursor, bool binary, const std::string& what) {
  return binary ? cursor.read_binary<int>(what) : static_cast<int>(cursor.expect_int(what));
}

void read_node_block_v4(TextCursor& cursor, bool binary, GmshData& data) {
  const int dim = read_int(cursor, binary, "entity dimension");
  read_int(cursor, binary, "entity tag");
  const int parametric = read_int(cursor, binary, "parametric flag");
  const long n = read_size(cursor, binary, "block node count");
  if (dim < 0 || dim > 3 || parametric < 0 || parametric > 1 || n < 0)
    throw cursor.error("invalid node block header");
  // A node is a tag and three coordinates: 4 numbers of text or 32 bytes.
  cursor.require_room(n, binary ? 32 : 8, "nodes", binary);
  std::vector<long> tags(n);
  for (long i = 0; i < n; ++i) tags[i] = read_size(cursor, binary, "node tag");
  const int values = 3 + (parametric ? dim : 0);
  std::vector<double> row(values);
  for (long i = 0; i < n; ++i) {
    for (int k = 0; k < values; ++k)
      row[k] = binary ? cursor.read_binary<double>("node coordinate")
                      : cursor.expect_double("node coordinate");
    add_node(data, tags[i], Eigen::Vector3d(row[0], row[1], row[2]), cursor);
  }
}

void read_nodes_v4(TextCursor& cursor, bool binary, GmshData& data) {
  if (binary) cursor.skip_line_end();
  const long blocks = read_size(cursor, binary, "node block count");
  const long count = read_size(cursor, binary, "node count");
  read_size(cursor, binary, "min node tag");
  read_size(cursor, binary, "max node tag");
  for (long b = 0; b < blocks; ++b) read_node_block_v4(cursor, binary, data);
  if (static_cast<long>(data.points.size()) != count)
    throw cursor.error("node blocks hold " + std::to_string(data.points.size()) +
                       " nodes, header declares " + std::to_string(count));
}

void read_element_block_v4(TextCursor& cursor, bool binary, GmshData& data) {
  read_int(cursor, binary, "entity dimension");
  const int entity = read_int(cursor, binary, "entity tag");
  const int type = read_int(cursor, binary, "element type");
  const long n = read_size(cursor, binary, "block element count");
  const int nodes = nodes_per_type(type);
  if (n < 0 || (binary && nodes == 0))
    throw cursor.error("invalid element block (type " + std::to_string(type) + ")");
  Record tokens;
  for (long i = 0; i < n; ++i) {
    std::array<long, 4> corner{};
    if (binary) {
      std::vector<std::uint64_t> record(1 + nodes);
      cursor.read_bytes(record.data(), record.size() * sizeof(std::uint64_t), "element record");
      if (type != kTetrahedron) continue;
      for (int a = 0; a < 4; ++a) corner[a] = static_cast<long>(record[1 + a]);
    } else {
      if (!cursor.next_record(tokens, false) || tokens[0].starts_with("$"))
        throw cursor.error("element block ended early (truncated file or wrong count?)");
      if (type != kTetrahedron) continue;
      if (tokens.size() != 5) throw cursor.error("tetrahedron line needs 5 values: tag + 4 nodes");
      for (int a = 0; a < 4; ++a) corner[a] = parse_int(tokens[1 + a], cursor, "node tag");
      data.lines.push_back(cursor.line());
    }
    data.tets.push_back(corner);
    data.tags.push_back(entity);
  }
}

void read_elements_v4(TextCursor& cursor, bool binary, GmshData& data) {
  if (binary) cursor.skip_line_end();
  const long blocks = read_size(cursor, binary, "element block count");
  read_size(cursor, binary, "element count");
  read_size(cursor, binary, "min element tag");
  read_size(cursor, binary, "max element tag");
  for (long b = 0; b < blocks; ++b) read_element_block_v4(cursor, binary, data);
}

// ---- assembly of the result ----

TetMesh resolve(const GmshData& data, const TextCursor& cursor) {
  TetMesh mesh;
  mesh.vertices.resize(static_cast<long>(data.points.size()), 3);
  for (std::size_t i = 0; i < data.points.size(); ++i) mesh.vertices.row(i) = data.points[i];
  mesh.tets.resize(static_cast<long>(data.tets.size()), 4);
  mesh.element_tags.resize(static_cast<long>(data.tets.size()));
  for (std::size_t t = 0; t < data.tets.size(); ++t) {
    for (int a = 0; a < 4; ++a) {
      const auto found = data.node_index.find(data.tets[t][a]);
      if (found == data.node_index.end()) {
        const std::string reason = "tetrahedron " + std::to_string(t) +
                                   " references undefined node " + std::to_string(data.tets[t][a]);
        throw data.lines.empty() ? Error(reason, ErrorContext{cursor.source(), -1, std::string()})
                                 : cursor.error_at(data.lines[t], reason);
      }
      mesh.tets(t, a) = found->second;
    }
    mesh.element_tags(t) = data.tags[t];
  }
  return mesh;
}

void read_section(TextCursor& cursor, const GmshFormat& format, std::string_view name,
                  GmshData& data) {
  if (name == "$Nodes") {
    if (!data.points.empty()) throw cursor.error("second $Nodes section is not supported");
    format.major == 2 ? read_nodes_v2(cursor, format.binary, data)
                      : read_nodes_v4(cursor, format.binary, data);
    if (format.binary) cursor.skip_line_end();
    expect_keyword(cursor, "$EndNodes", " (node count in the header wrong?)");
  } else if (name == "$Elements") {
    format.major == 2 ? read_elements_v2(cursor, format.binary, data)
                      : read_elements_v4(cursor, format.binary, data);
    if (format.binary) cursor.skip_line_end();
    expect_keyword(cursor, "$EndElements", " (element count in the header wrong?)");
  } else if (name.starts_with("$")) {
    cursor.skip_past("$End" + std::string(name.substr(1)));
  } else {
    throw cursor.error("expected a $Section, found '" + std::string(name) + "'");
  }
}

}  // namespace

TetMesh read_gmsh(const std::filesystem::path& path, const TetMeshReadOptions& options) {
  TextCursor cursor(path);
  const GmshFormat format = read_format(cursor);
  GmshData data;
  std::string_view name;
  while (cursor.next_token(name)) read_section(cursor, format, name, data);
  if (data.points.empty()) throw cursor.error("no $Nodes section");
  if (data.tets.empty()) throw cursor.error("no 4-node tetrahedra (element type 4) found");
  TetMesh mesh = resolve(data, cursor);
  check_tet_mesh(mesh, options, cursor.source(), data.lines);
  return mesh;
}

}  // namespace mgelastic::geometry
