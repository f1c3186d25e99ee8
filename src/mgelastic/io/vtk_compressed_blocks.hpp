#pragma once
// VTK's zlib block layout for binary data arrays (vtkZLibDataCompressor, VTKFile header_type
// "UInt64"), the bytes one array contributes to a file's appended data:
//
//   UInt64 header: [number of blocks B, block size, size of the last block, compressed size of
//                   block 0, ..., compressed size of block B-1]
//   then the B blocks, each one zlib stream (RFC 1950) of up to `block size` bytes of the array.
//
// Sizes count bytes, little-endian. Every block but the last holds `block size` bytes; the last
// holds the remainder, and "size of the last block" is 0 when it is full, as VTK writes it (an
// empty array has B = 0). Blocks are compressed independently, so they are compressed in parallel
// (OpenMP) and the bytes do not depend on the number of threads.
//
// The deflate encoder is libdeflate when the build found it (MGELASTIC_HAVE_LIBDEFLATE; level 1),
// zlib level 1 with Z_RLE otherwise. On the 256^3 frame of `mgelastic bench vtk`, libdeflate is
// 1.3x as fast as zlib Z_RLE (2.9x zlib level 1) for a 2 % larger file
// (docs/notes/2026-12-07-performance-history.md). Both write standard zlib streams, so readers
// see no difference, but the bytes differ between the two builds.
#include <cstddef>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace mgelastic::io {

// Large blocks keep the header short and let threads share the work; ParaView reads any size.
inline constexpr std::size_t kVtkBlockBytes = std::size_t(1) << 18;

// The compressed bytes of one array: header then blocks, kept as separate pieces so that
// nothing is concatenated before the file is written.
struct CompressedArray {
  std::vector<std::string> pieces;
  std::size_t bytes = 0;  // total size of the pieces
};

// The bytes [begin, begin + scratch.size()) of an array: either a view into the array itself
// (no copy) or `scratch` filled with them (a converted copy of that block only).
using BlockSource =
    std::function<std::span<const std::byte>(std::size_t begin, std::span<std::byte> scratch)>;

// Compresses an array of `bytes` bytes read block by block from `source`. `block_bytes` must be
// below 4 GiB. Throws mgelastic::Error when the encoder fails (out of memory).
CompressedArray compress_blocks(std::size_t bytes, const BlockSource& source,
                                std::size_t block_bytes = kVtkBlockBytes);

// Appends the header and the compressed blocks of `data` to `out`.
void append_compressed_blocks(std::string& out, std::span<const std::byte> data,
                              std::size_t block_bytes = kVtkBlockBytes);

}  // namespace mgelastic::io
