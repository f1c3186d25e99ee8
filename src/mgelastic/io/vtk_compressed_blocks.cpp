#include "mgelastic/io/vtk_compressed_blocks.hpp"

#ifdef MGELASTIC_HAVE_LIBDEFLATE
#include <libdeflate.h>
#else
#include <zlib.h>
#endif

#include <algorithm>
#include <bit>
#include <cstdint>
#include <memory>

#include "mgelastic/core/error.hpp"

namespace mgelastic::io {
namespace {

#ifdef MGELASTIC_HAVE_LIBDEFLATE
// One block as a zlib stream (what VTK inflates with uncompress) in `compressed`, or false when
// the encoder fails. Level 1: lattice frames are large and written every frame, and level 6
// saves ~10 % of the file for 1.4x the time.
class BlockCompressor {
 public:
  BlockCompressor() : m_compressor(libdeflate_alloc_compressor(1)) {}
  bool compress(std::span<const std::byte> block, std::string& compressed) {
    if (!m_compressor) return false;
    m_scratch.resize(libdeflate_zlib_compress_bound(m_compressor.get(), block.size()));
    const std::size_t size = libdeflate_zlib_compress(
        m_compressor.get(), block.data(), block.size(), m_scratch.data(), m_scratch.size());
    compressed.assign(m_scratch.data(), size);
    return size > 0;
  }

 private:
  struct Free {
    void operator()(libdeflate_compressor* c) const { libdeflate_free_compressor(c); }
  };
  std::unique_ptr<libdeflate_compressor, Free> m_compressor;
  std::string m_scratch;
};
#else
// zlib level 1 with run-length matching only (Z_BEST_SPEED, Z_RLE): float mantissas hold almost
// no repeated strings, so searching for them (the default strategy) costs twice the time; runs
// (zeros outside the body) and the entropy of exponent bytes are still coded.
class BlockCompressor {
 public:
  bool compress(std::span<const std::byte> block, std::string& compressed) {
    z_stream stream{};
    if (deflateInit2(&stream, Z_BEST_SPEED, Z_DEFLATED, 15, 8, Z_RLE) != Z_OK) return false;
    m_scratch.resize(deflateBound(&stream, static_cast<uLong>(block.size())));
    stream.next_in = reinterpret_cast<Bytef*>(const_cast<std::byte*>(block.data()));
    stream.avail_in = static_cast<uInt>(block.size());
    stream.next_out = reinterpret_cast<Bytef*>(m_scratch.data());
    stream.avail_out = static_cast<uInt>(m_scratch.size());
    const int status = deflate(&stream, Z_FINISH);
    compressed.assign(m_scratch.data(), stream.total_out);
    deflateEnd(&stream);
    return status == Z_STREAM_END;
  }

 private:
  std::string m_scratch;
};
#endif

}  // namespace

CompressedArray compress_blocks(std::size_t bytes, const BlockSource& source,
                                std::size_t block_bytes) {
  const std::size_t blocks = (bytes + block_bytes - 1) / block_bytes;
  CompressedArray result;
  result.pieces.resize(blocks + 1);  // the header, then the blocks
  bool failed = false;
  const auto count = static_cast<std::ptrdiff_t>(blocks);
  // Each thread writes only its own blocks, reading (or converting) them straight from the
  // array into its scratch buffer; the pieces stay in block order.
#pragma omp parallel if (blocks > 1) reduction(|| : failed)
  {
    BlockCompressor compressor;
    std::vector<std::byte> scratch(std::min(block_bytes, bytes));
#pragma omp for schedule(dynamic)
    for (std::ptrdiff_t b = 0; b < count; ++b) {
      const std::size_t begin = static_cast<std::size_t>(b) * block_bytes;
      const std::span<std::byte> buffer(scratch.data(), std::min(block_bytes, bytes - begin));
      failed = failed || !compressor.compress(source(begin, buffer), result.pieces[b + 1]);
    }
  }
  if (failed) throw Error("could not compress a VTK data block (out of memory?)");
  std::vector<std::uint64_t> header = {blocks, block_bytes, bytes % block_bytes};
  for (std::size_t b = 0; b < blocks; ++b) header.push_back(result.pieces[b + 1].size());
  static_assert(std::endian::native == std::endian::little, "VTK files are written LittleEndian");
  result.pieces[0].assign(reinterpret_cast<const char*>(header.data()),
                          header.size() * sizeof(std::uint64_t));
  for (const std::string& piece : result.pieces) result.bytes += piece.size();
  return result;
}

void append_compressed_blocks(std::string& out, std::span<const std::byte> data,
                              std::size_t block_bytes) {
  const CompressedArray compressed = compress_blocks(
      data.size(),
      [&](std::size_t begin, std::span<std::byte> scratch) {
        return data.subspan(begin, scratch.size());
      },
      block_bytes);
  for (const std::string& piece : compressed.pieces) out += piece;
}

}  // namespace mgelastic::io
