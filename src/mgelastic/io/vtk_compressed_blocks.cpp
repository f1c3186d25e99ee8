#include "mgelastic/io/vtk_compressed_blocks.hpp"

#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <vector>

#include "mgelastic/core/error.hpp"

namespace mgelastic::io {
namespace {

// One block as a zlib stream; an empty string when zlib fails.
std::string compress_block(std::span<const std::byte> block) {
  uLongf size = compressBound(static_cast<uLong>(block.size()));
  std::string compressed(size, '\0');
  const int status =
      compress2(reinterpret_cast<Bytef*>(compressed.data()), &size,
                reinterpret_cast<const Bytef*>(block.data()), block.size(), Z_BEST_SPEED);
  if (status != Z_OK) return {};
  compressed.resize(size);
  return compressed;
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
