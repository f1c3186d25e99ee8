#include "mgelastic/io/vtk_compressed_blocks.hpp"

#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <vector>

#include "mgelastic/core/error.hpp"

namespace mgelastic::io {
namespace {

// One block as a zlib stream (what VTK inflates with uncompress); an empty string when zlib
// fails. Z_RLE: float mantissas hold almost no repeated strings, so searching for them (the
// default strategy) costs twice the time for ~10% smaller files; runs (zeros outside the body)
// and the entropy of exponent bytes are still coded.
std::string compress_block(std::span<const std::byte> block) {
  z_stream stream{};
  if (deflateInit2(&stream, Z_BEST_SPEED, Z_DEFLATED, 15, 8, Z_RLE) != Z_OK) return {};
  std::string compressed(deflateBound(&stream, static_cast<uLong>(block.size())), '\0');
  stream.next_in = reinterpret_cast<Bytef*>(const_cast<std::byte*>(block.data()));
  stream.avail_in = static_cast<uInt>(block.size());
  stream.next_out = reinterpret_cast<Bytef*>(compressed.data());
  stream.avail_out = static_cast<uInt>(compressed.size());
  const int status = deflate(&stream, Z_FINISH);
  compressed.resize(stream.total_out);
  deflateEnd(&stream);
  return status == Z_STREAM_END ? compressed : std::string();
}

}  // namespace

void append_compressed_blocks(std::string& out, std::span<const std::byte> data,
                              std::size_t block_bytes) {
  const std::size_t blocks = (data.size() + block_bytes - 1) / block_bytes;
  std::vector<std::string> compressed(blocks);
  // Each thread writes only its own blocks; the blocks are joined in order afterwards.
  const auto count = static_cast<std::ptrdiff_t>(blocks);
#pragma omp parallel for schedule(dynamic) if (blocks > 1)
  for (std::ptrdiff_t b = 0; b < count; ++b) {
    const std::size_t begin = static_cast<std::size_t>(b) * block_bytes;
    compressed[b] = compress_block(data.subspan(begin, std::min(block_bytes, data.size() - begin)));
  }
  std::vector<std::uint64_t> header = {blocks, block_bytes, data.size() % block_bytes};
  for (const std::string& c : compressed) {
    // A zlib stream is never empty, so an empty block is a failure.
    if (c.empty()) throw Error("zlib could not compress a VTK data block (out of memory?)");
    header.push_back(c.size());
  }
  static_assert(std::endian::native == std::endian::little, "VTK files are written LittleEndian");
  out.append(reinterpret_cast<const char*>(header.data()), header.size() * sizeof(std::uint64_t));
  for (const std::string& c : compressed) out += c;
}

}  // namespace mgelastic::io
