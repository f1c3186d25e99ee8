// PLY reader: a text header declares elements and their typed properties; the data follows as
// text (ascii) or packed binary in either byte order. Only the vertex positions and the face
// index lists are kept; everything else is skipped by its declared type, so unknown properties
// cannot desynchronize the reader.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "mgelastic/geometry/surface_mesh_builder.hpp"
#include "mgelastic/geometry/surface_mesh_readers.hpp"

namespace mgelastic::geometry {
namespace {

using detail::SurfaceMeshBuilder;
using detail::TextCursor;

enum class PlyType { INT8, UINT8, INT16, UINT16, INT32, UINT32, FLOAT32, FLOAT64 };
enum class PlyFormat { ASCII, BINARY_LITTLE_ENDIAN, BINARY_BIG_ENDIAN };

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::FLOAT32;  // of the value, or of the list items
  bool is_list = false;
  PlyType count_type = PlyType::UINT8;
};

struct PlyElement {
  std::string name;
  long count = 0;
  std::vector<PlyProperty> properties;
};

struct PlyHeader {
  PlyFormat format = PlyFormat::ASCII;
  std::vector<PlyElement> elements;
};

PlyType parse_type(std::string_view name, const TextCursor& cursor) {
  static const std::map<std::string_view, PlyType> types = {
      {"char", PlyType::INT8},      {"int8", PlyType::INT8},       {"uchar", PlyType::UINT8},
      {"uint8", PlyType::UINT8},    {"short", PlyType::INT16},     {"int16", PlyType::INT16},
      {"ushort", PlyType::UINT16},  {"uint16", PlyType::UINT16},   {"int", PlyType::INT32},
      {"int32", PlyType::INT32},    {"uint", PlyType::UINT32},     {"uint32", PlyType::UINT32},
      {"float", PlyType::FLOAT32},  {"float32", PlyType::FLOAT32}, {"double", PlyType::FLOAT64},
      {"float64", PlyType::FLOAT64}};
  const auto it = types.find(name);
  if (it == types.end()) throw cursor.error("unknown PLY type '" + std::string(name) + "'");
  return it->second;
}

bool is_integer(PlyType type) {
  return type != PlyType::FLOAT32 && type != PlyType::FLOAT64;
}

PlyFormat parse_format(const std::vector<std::string_view>& tokens, const TextCursor& cursor) {
  if (tokens.size() != 3) throw cursor.error("expected 'format <kind> 1.0'");
  if (tokens[1] == "ascii") return PlyFormat::ASCII;
  if (tokens[1] == "binary_little_endian") return PlyFormat::BINARY_LITTLE_ENDIAN;
  if (tokens[1] == "binary_big_endian") return PlyFormat::BINARY_BIG_ENDIAN;
  throw cursor.error("unknown PLY format '" + std::string(tokens[1]) + "'");
}

PlyProperty parse_property(const std::vector<std::string_view>& tokens, const TextCursor& cursor) {
  PlyProperty property;
  if (tokens.size() == 5 && tokens[1] == "list") {
    property.is_list = true;
    property.count_type = parse_type(tokens[2], cursor);
    property.type = parse_type(tokens[3], cursor);
    if (!is_integer(property.count_type)) throw cursor.error("list count type must be an integer");
  } else if (tokens.size() == 3) {
    property.type = parse_type(tokens[1], cursor);
  } else {
    throw cursor.error("expected 'property <type> <name>' or 'property list <type> <type> <name>'");
  }
  property.name = std::string(tokens.back());
  return property;
}

void parse_header_line(const std::vector<std::string_view>& tokens, TextCursor& cursor,
                       PlyHeader& header) {
  const std::string_view keyword = tokens[0];
  if (keyword == "format") {
    header.format = parse_format(tokens, cursor);
  } else if (keyword == "element") {
    if (tokens.size() != 3) throw cursor.error("expected 'element <name> <count>'");
    const long count = detail::parse_int(tokens[2], cursor, "element count");
    if (count < 0) throw cursor.error("negative element count");
    header.elements.push_back({std::string(tokens[1]), count, {}});
  } else if (keyword == "property") {
    if (header.elements.empty()) throw cursor.error("property before any element");
    header.elements.back().properties.push_back(parse_property(tokens, cursor));
  } else if (keyword != "comment" && keyword != "obj_info") {
    throw cursor.error("unknown PLY header keyword '" + std::string(keyword) + "'");
  }
}

PlyHeader read_header(TextCursor& cursor) {
  std::vector<std::string_view> tokens;
  if (!cursor.next_record(tokens, false) || tokens[0] != "ply")
    throw cursor.error("not a PLY file (first line is not 'ply')");
  PlyHeader header;
  while (true) {
    if (!cursor.next_record(tokens, false)) throw cursor.error("missing 'end_header'");
    if (tokens[0] == "end_header") break;
    parse_header_line(tokens, cursor, header);
  }
  cursor.skip_line_end();  // binary data starts right after the header's last newline
  return header;
}

// Reads PLY values of declared types from the data section in its format.
class PlyValueReader {
 public:
  PlyValueReader(TextCursor& cursor, PlyFormat format) : m_cursor(cursor), m_format(format) {}

  double value(PlyType type, const std::string& what) {
    if (m_format == PlyFormat::ASCII)
      return is_integer(type) ? double(m_cursor.expect_int(what)) : m_cursor.expect_double(what);
    switch (type) {
      case PlyType::INT8:
        return binary<std::int8_t>(what);
      case PlyType::UINT8:
        return binary<std::uint8_t>(what);
      case PlyType::INT16:
        return binary<std::int16_t>(what);
      case PlyType::UINT16:
        return binary<std::uint16_t>(what);
      case PlyType::INT32:
        return binary<std::int32_t>(what);
      case PlyType::UINT32:
        return binary<std::uint32_t>(what);
      case PlyType::FLOAT32:
        return binary<float>(what);
      case PlyType::FLOAT64:
        return binary<double>(what);
    }
    return 0.0;
  }

  // Reads a list property: integer items into `items`, floating-point items are only skipped
  // (index lists are integers; a float list is some other property).
  void list(const PlyProperty& property, std::vector<long>& items, const std::string& what) {
    const double n = value(property.count_type, what + " count");
    if (n < 0) throw error("negative list length in " + what);
    // Grow item by item: a corrupt length then ends in a truncation error, not a huge allocation.
    items.clear();
    for (double i = 0; i < n; ++i) {
      if (is_integer(property.type)) {
        items.push_back(integer(property.type, what));
      } else {
        value(property.type, what);
      }
    }
  }

  // An integer value read as such: ASCII integers beyond 2^53 must not round through double.
  long integer(PlyType type, const std::string& what) {
    if (m_format == PlyFormat::ASCII) return m_cursor.expect_int(what);
    return static_cast<long>(value(type, what));  // exact: binary integers have at most 32 bits
  }

  Error error(const std::string& reason) const {
    return m_format == PlyFormat::ASCII ? m_cursor.error(reason) : m_cursor.binary_error(reason);
  }

 private:
  template <class T>
  double binary(const std::string& what) {
    const bool big = m_format == PlyFormat::BINARY_BIG_ENDIAN;
    return static_cast<double>(detail::read_binary_value<T>(m_cursor, big, what));
  }

  TextCursor& m_cursor;
  PlyFormat m_format;
};

int find_property(const PlyElement& element, std::initializer_list<std::string_view> names,
                  const TextCursor& cursor) {
  for (std::size_t p = 0; p < element.properties.size(); ++p)
    for (const std::string_view name : names)
      if (element.properties[p].name == name) return static_cast<int>(p);
  throw cursor.error("element '" + element.name + "' has no property '" +
                     std::string(*names.begin()) + "'");
}

void read_vertices(const PlyElement& element, PlyValueReader& reader, const TextCursor& cursor,
                   SurfaceMeshBuilder& builder) {
  const int axes[3] = {find_property(element, {"x"}, cursor), find_property(element, {"y"}, cursor),
                       find_property(element, {"z"}, cursor)};
  std::vector<long> skipped;
  double x[3] = {0.0, 0.0, 0.0};
  for (long v = 0; v < element.count; ++v) {
    for (int p = 0; p < static_cast<int>(element.properties.size()); ++p) {
      const PlyProperty& property = element.properties[p];
      if (property.is_list) {
        reader.list(property, skipped, "vertex property " + property.name);
        continue;
      }
      const double value = reader.value(property.type, "vertex property " + property.name);
      for (int a = 0; a < 3; ++a) x[a] = p == axes[a] ? value : x[a];
    }
    builder.add_vertex(x[0], x[1], x[2]);
  }
}

void read_faces(const PlyElement& element, long vertex_count, PlyValueReader& reader,
                const TextCursor& cursor, SurfaceMeshBuilder& builder) {
  const int indices = find_property(element, {"vertex_indices", "vertex_index"}, cursor);
  const PlyProperty& index_property = element.properties[indices];
  if (!index_property.is_list || !is_integer(index_property.type))
    throw cursor.error("face property '" + index_property.name + "' must be a list of integers");
  std::vector<long> corners;
  std::vector<long> skipped;
  for (long f = 0; f < element.count; ++f) {
    for (int p = 0; p < static_cast<int>(element.properties.size()); ++p) {
      const PlyProperty& property = element.properties[p];
      if (p == indices) {
        reader.list(property, corners, "face vertex indices");
      } else if (property.is_list) {
        reader.list(property, skipped, "face property " + property.name);
      } else {
        reader.value(property.type, "face property " + property.name);
      }
    }
    builder.add_polygon(corners, vertex_count, 0);
  }
}

void skip_element(const PlyElement& element, PlyValueReader& reader) {
  if (element.properties.empty()) return;  // no data, whatever the (maybe huge) count says
  std::vector<long> skipped;
  for (long i = 0; i < element.count; ++i)
    for (const PlyProperty& property : element.properties)
      if (property.is_list) {
        reader.list(property, skipped, element.name + " property " + property.name);
      } else {
        reader.value(property.type, element.name + " property " + property.name);
      }
}

long declared_vertex_count(const PlyHeader& header, const TextCursor& cursor) {
  for (const PlyElement& element : header.elements)
    if (element.name == "vertex") return element.count;
  throw cursor.error("no 'vertex' element in the header");
}

long declared_face_count(const PlyHeader& header) {
  for (const PlyElement& element : header.elements)
    if (element.name == "face") return element.count;
  return 0;
}

// Counts in the header must account for all the data: leftovers mean a corrupt file.
void expect_end(TextCursor& cursor, const PlyValueReader& reader) {
  std::string_view token;
  if (cursor.next_token(token))
    throw reader.error("data after the last element (header counts do not match the data)");
}

}  // namespace

TriangleMesh read_ply(const std::filesystem::path& path) {
  TextCursor cursor(path);
  const PlyHeader header = read_header(cursor);
  const long vertex_count = declared_vertex_count(header, cursor);
  SurfaceMeshBuilder builder(cursor, header.format != PlyFormat::ASCII);
  builder.reserve(vertex_count, declared_face_count(header));
  PlyValueReader reader(cursor, header.format);
  for (const PlyElement& element : header.elements) {
    if (element.name == "vertex") {
      read_vertices(element, reader, cursor, builder);
    } else if (element.name == "face") {
      read_faces(element, vertex_count, reader, cursor, builder);
    } else {
      skip_element(element, reader);
    }
  }
  expect_end(cursor, reader);
  return builder.finish();
}

}  // namespace mgelastic::geometry
