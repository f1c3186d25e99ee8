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
#include <cstddef>
#include <span>
#include <string>

namespace mgelastic::io {

// Large blocks keep the header short and let threads share the work; ParaView reads any size.
inline constexpr std::size_t kVtkBlockBytes = std::size_t(1) << 18;

// Appends the header and the compressed blocks of `data` to `out`. zlib level 1 with run-length
// matching only (Z_BEST_SPEED, Z_RLE): lattice frames are large and written every frame, and
// searching harder gains little on float data. `block_bytes` must be below 4 GiB.
// Throws mgelastic::Error when zlib fails (out of memory).
void append_compressed_blocks(std::string& out, std::span<const std::byte> data,
                              std::size_t block_bytes = kVtkBlockBytes);

}  // namespace mgelastic::io
