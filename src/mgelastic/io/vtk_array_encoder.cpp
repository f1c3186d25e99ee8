#include "mgelastic/io/vtk_array_encoder.hpp"

#include <charconv>

#include "mgelastic/io/vtk_compressed_blocks.hpp"

namespace mgelastic::io {
namespace {

template <typename T>
constexpr const char* vtk_type_name() {
  if constexpr (std::is_same_v<T, float>) return "Float32";
  if constexpr (std::is_same_v<T, double>) return "Float64";
  if constexpr (std::is_same_v<T, std::int32_t>) return "Int32";
  if constexpr (std::is_same_v<T, std::int64_t>) return "Int64";
  if constexpr (std::is_same_v<T, std::uint8_t>) return "UInt8";
}

// Shortest text that reads back to the same value (std::to_chars), nine values a line.
template <typename T>
void write_text(std::ostream& out, std::span<const T> values) {
  char number[32];
  std::string line;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const auto end = std::to_chars(number, number + sizeof number, values[i]).ptr;
    line.append(number, end);
    line += (i + 1) % 9 && i + 1 < values.size() ? ' ' : '\n';
    if (line.size() > 4096) {
      out << line;
      line.clear();
    }
  }
  out << line;
}

}  // namespace

std::string VtkArrayEncoder::file_attributes() const {
  std::string attributes = "version=\"1.0\" byte_order=\"LittleEndian\"";
  if (m_encoding == VtkEncoding::BINARY)
    attributes += " header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\"";
  return attributes;
}

template <typename T>
void VtkArrayEncoder::write(std::ostream& out, const std::string& attributes,
                            std::span<const T> values) {
  out << "<DataArray type=\"" << vtk_type_name<T>() << '"' << (attributes.empty() ? "" : " ")
      << attributes;
  if (m_encoding == VtkEncoding::ASCII) {
    out << " format=\"ascii\">\n";
    write_text(out, values);
  } else {
    out << " format=\"appended\" offset=\"" << m_appended.size() << "\">\n";
    append_compressed_blocks(m_appended, std::as_bytes(values));
  }
  out << "</DataArray>\n";
}

template void VtkArrayEncoder::write(std::ostream&, const std::string&, std::span<const float>);
template void VtkArrayEncoder::write(std::ostream&, const std::string&, std::span<const double>);
template void VtkArrayEncoder::write(std::ostream&, const std::string&,
                                     std::span<const std::int32_t>);
template void VtkArrayEncoder::write(std::ostream&, const std::string&,
                                     std::span<const std::int64_t>);
template void VtkArrayEncoder::write(std::ostream&, const std::string&,
                                     std::span<const std::uint8_t>);

void VtkArrayEncoder::write_appended(std::ostream& out) const {
  if (m_encoding == VtkEncoding::ASCII) return;
  out << "<AppendedData encoding=\"raw\">\n_";
  out.write(m_appended.data(), static_cast<std::streamsize>(m_appended.size()));
  out << "\n</AppendedData>\n";
}

}  // namespace mgelastic::io
