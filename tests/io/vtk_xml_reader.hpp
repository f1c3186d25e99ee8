#pragma once
// A reader of VTK XML files for the tests, written from the VTK XML file-format description and
// independent of the writers: it finds each <DataArray> start tag, and reads ASCII values from
// the element's text, or appended values at `offset` bytes after the '_' of
// <AppendedData encoding="raw">: with compressor="vtkZLibDataCompressor" and header_type="UInt64",
// a header [blocks, block size, last block size (0 = full), compressed sizes...] and the zlib
// blocks, each inflated with zlib's uncompress.
#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace mgelastic::test {

struct VtkArray {
  std::string type, format;
  std::vector<double> values;  // every VTK scalar type the writers use is exact as a double
};

// An array's bytes inflated from the appended section; fails the test on a malformed layout.
inline std::string inflate_appended(const std::string& raw, std::size_t offset) {
  auto word = [&](std::size_t i) {
    std::uint64_t w = 0;
    EXPECT_LE(offset + 8 * (i + 1), raw.size());
    if (offset + 8 * (i + 1) <= raw.size()) std::memcpy(&w, raw.data() + offset + 8 * i, 8);
    return w;
  };
  const std::uint64_t blocks = word(0), block_size = word(1), last_size = word(2);
  std::string bytes;
  std::size_t position = offset + 8 * (3 + blocks);
  for (std::uint64_t b = 0; b < blocks; ++b) {
    const std::uint64_t compressed = word(3 + b);
    const bool partial = b + 1 == blocks && last_size != 0;
    uLongf size = partial ? last_size : block_size;
    std::string block(size, '\0');
    EXPECT_LE(position + compressed, raw.size());
    EXPECT_EQ(uncompress(reinterpret_cast<Bytef*>(block.data()), &size,
                         reinterpret_cast<const Bytef*>(raw.data() + position), compressed),
              Z_OK);
    EXPECT_EQ(size, partial ? last_size : block_size) << "block " << b;
    bytes += block;
    position += compressed;
  }
  return bytes;
}

template <typename T>
std::vector<double> reinterpret_bytes(const std::string& bytes) {
  EXPECT_EQ(bytes.size() % sizeof(T), 0u);
  std::vector<T> typed(bytes.size() / sizeof(T));
  // An empty vector's data() may be null, which memcpy must not get even for 0 bytes (UBSan).
  if (!typed.empty()) std::memcpy(typed.data(), bytes.data(), typed.size() * sizeof(T));
  return {typed.begin(), typed.end()};
}

inline std::vector<double> decode(const std::string& type, const std::string& bytes) {
  if (type == "Float32") return reinterpret_bytes<float>(bytes);
  if (type == "Float64") return reinterpret_bytes<double>(bytes);
  if (type == "Int32") return reinterpret_bytes<std::int32_t>(bytes);
  if (type == "Int64") return reinterpret_bytes<std::int64_t>(bytes);
  if (type == "UInt8") return reinterpret_bytes<std::uint8_t>(bytes);
  ADD_FAILURE() << "unexpected type " << type;
  return {};
}

inline std::string attribute(const std::string& tag, const std::string& key) {
  std::smatch m;
  if (std::regex_search(tag, m, std::regex(" " + key + "=\"([^\"]*)\""))) return m[1];
  return {};
}

struct VtkFile {
  std::string xml;  // the text before <AppendedData> (all of it for ASCII files)
  std::string raw;  // the bytes after the '_' of <AppendedData>
  std::map<std::string, VtkArray> arrays;  // by Name; unnamed ones as "Points"
};

inline VtkFile read_vtk(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  VtkFile file;
  const std::size_t appended = text.find("<AppendedData encoding=\"raw\">");
  file.xml = text.substr(0, appended);
  if (appended != std::string::npos) file.raw = text.substr(text.find('_', appended) + 1);
  for (std::size_t at = file.xml.find("<DataArray"); at != std::string::npos;
       at = file.xml.find("<DataArray", at + 1)) {
    const std::size_t tag_end = file.xml.find('>', at);
    const std::string tag = file.xml.substr(at, tag_end - at);
    VtkArray array{attribute(tag, "type"), attribute(tag, "format"), {}};
    if (array.format == "ascii") {
      std::istringstream values(
          file.xml.substr(tag_end + 1, file.xml.find("</DataArray>", at) - tag_end - 1));
      // Float32 text is the shortest decimal of a float: read it as one.
      for (std::string v; values >> v;)
        array.values.push_back(array.type == "Float32" ? std::stof(v) : std::stod(v));
    } else {
      EXPECT_EQ(array.format, "appended");
      array.values =
          decode(array.type, inflate_appended(file.raw, std::stoull(attribute(tag, "offset"))));
    }
    const std::string name = attribute(tag, "Name");
    file.arrays[name.empty() ? "Points" : name] = array;
  }
  return file;
}

}  // namespace mgelastic::test
