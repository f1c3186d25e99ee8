#pragma once
// The DataArray elements of one VTK XML file, in one encoding (VTK file formats, "XML File
// Formats"). ASCII: the values inline as text. Binary (the default): each array's bytes are
// zlib-compressed in blocks (vtk_compressed_blocks.hpp) and kept; its element says
// format="appended" offset="N", and write_appended() writes all of them after the XML as
//
//   <AppendedData encoding="raw">
//   _<bytes of the first array><bytes of the second array>...
//   </AppendedData>
//
// where N counts bytes from the one after the '_'. The VTKFile element must then announce the
// compressor and the UInt64 header type (file_attributes()).
#include <cstdint>
#include <ostream>
#include <span>
#include <string>
#include <vector>

#include "mgelastic/io/vtk_compressed_blocks.hpp"

namespace mgelastic::io {

enum class VtkEncoding {
  BINARY,  // appended raw bytes, zlib-compressed: small files, fast to write and read
  ASCII    // inline text: readable by eye and by tools without zlib, slow and large
};

class VtkArrayEncoder {
 public:
  explicit VtkArrayEncoder(VtkEncoding encoding) : m_encoding(encoding) {}

  // The VTKFile attributes after `type`: version, byte order and, for binary data, the
  // compressor and the header type.
  std::string file_attributes() const;

  // Writes one <DataArray> element holding `values` (tuples contiguous) stored as type T;
  // `attributes` are written into the start tag as they are (Name, NumberOfComponents; may be
  // empty). T is one of float, double, std::int32_t, std::int64_t, std::uint8_t; the source type S
  // is T itself or double (converted block by block while compressing, no whole-array copy).
  template <typename T, typename S = T>
  void write(std::ostream& out, const std::string& attributes, std::span<const S> values);

  // Writes the <AppendedData> section of the binary arrays (nothing for ASCII): after the data
  // set element, before </VTKFile>.
  void write_appended(std::ostream& out) const;

 private:
  VtkEncoding m_encoding;
  std::vector<CompressedArray> m_appended;  // the arrays written so far, in file order
  std::size_t m_appended_bytes = 0;         // their total size: the next array's offset
};

}  // namespace mgelastic::io
