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
template <typename T, typename S>
void write_text(std::ostream& out, std::span<const S> values) {
  char number[32];
  std::string line;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const auto end = std::to_chars(number, number + sizeof number, static_cast<T>(values[i])).ptr;
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

template <typename T, typename S>
void VtkArrayEncoder::write(std::ostream& out, const std::string& attributes,
                            std::span<const S> values) {
  out << "<DataArray type=\"" << vtk_type_name<T>() << '"' << (attributes.empty() ? "" : " ")
      << attributes;
  if (m_encoding == VtkEncoding::ASCII) {
    out << " format=\"ascii\">\n";
    write_text<T>(out, values);
  } else {
    out << " format=\"appended\" offset=\"" << m_appended_bytes << "\">\n";
    // Blocks hold whole values (kVtkBlockBytes is a multiple of sizeof(T)).
    static_assert(kVtkBlockBytes % sizeof(T) == 0);
    const BlockSource source = [values](std::size_t begin, std::span<std::byte> scratch) {
      if constexpr (std::is_same_v<T, S>) {
        return std::as_bytes(values).subspan(begin, scratch.size());
      } else {
        const std::span<T> converted(reinterpret_cast<T*>(scratch.data()),
                                     scratch.size() / sizeof(T));
        const S* from = values.data() + begin / sizeof(T);
        for (std::size_t i = 0; i < converted.size(); ++i) converted[i] = static_cast<T>(from[i]);
        return std::span<const std::byte>(scratch);
      }
    };
    m_appended.push_back(compress_blocks(values.size() * sizeof(T), source));
    m_appended_bytes += m_appended.back().bytes;
  }
  out << "</DataArray>\n";
}

template void VtkArrayEncoder::write<float>(std::ostream&, const std::string&,
                                            std::span<const float>);
template void VtkArrayEncoder::write<double>(std::ostream&, const std::string&,
                                             std::span<const double>);
template void VtkArrayEncoder::write<std::int32_t>(std::ostream&, const std::string&,
                                                   std::span<const std::int32_t>);
template void VtkArrayEncoder::write<std::int64_t>(std::ostream&, const std::string&,
                                                   std::span<const std::int64_t>);
template void VtkArrayEncoder::write<std::uint8_t>(std::ostream&, const std::string&,
                                                   std::span<const std::uint8_t>);
template void VtkArrayEncoder::write<float, double>(std::ostream&, const std::string&,
                                                    std::span<const double>);
template void VtkArrayEncoder::write<std::int32_t, double>(std::ostream&, const std::string&,
                                                           std::span<const double>);
template void VtkArrayEncoder::write<std::uint8_t, double>(std::ostream&, const std::string&,
                                                           std::span<const double>);

void VtkArrayEncoder::write_appended(std::ostream& out) const {
  if (m_encoding == VtkEncoding::ASCII) return;
  out << "<AppendedData encoding=\"raw\">\n_";
  for (const CompressedArray& array : m_appended)
    for (const std::string& piece : array.pieces)
      out.write(piece.data(), static_cast<std::streamsize>(piece.size()));
  out << "\n</AppendedData>\n";
}

}  // namespace mgelastic::io
