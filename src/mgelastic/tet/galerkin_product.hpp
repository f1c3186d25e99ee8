#pragma once
// Galerkin coarse operators E = R K R^T with R = P^T (Georgii & Westermann 2008, Sec. 4.3),
// on block-row-compressed matrices with 3x3 blocks (brc_matrix.hpp).
//
// With P given per fine vertex i as four pairs (coarse vertex a, weight w_ia) (tet_hierarchy.hpp)
// the product is, per fine block K_ij (stored in row i of K),
//   E_ab += w_ia w_jb K_ij     for every pair (a, w_ia) of i and (b, w_jb) of j       (Eq. 9)
// (the same sum as Eq. 9 ordered by the non-zero blocks of K, as in Algorithm 1). Weights that are
// zero (Dirichlet rows of P) contribute nothing.
//
// * galerkin_pattern: the coarse block pattern {(a, b)} of that sum plus every diagonal block,
//   computed once per level.
// * galerkin_naive: the sum evaluated directly, each destination block found by binary search in
//   E's row (the "standard operations" baseline of Table 1), serial.
// * GalerkinStream: Algorithm 1. Built once per level; each update walks the streams without any
//   search. Layout of one stream:
//     control: bytes; bit 7 set = fetch the next block of K (the cursor starts just before
//              `first_block`, blocks of K are contiguous in its BRC value array, so "next" is
//              k + 1), bits 0-6 = number of (weight, destination) pairs to apply with the current
//              block. A block with more than 127 pairs continues with further bytes whose bit 7 is
//              clear. A block of K that feeds nothing in this stream costs one byte 0x80.
//     data:    per pair, weight w_ia w_jb (double) and the index of block (a, b) in E's value
//              array (int32), in two aligned arrays (12 bytes per pair).
//   Symmetry: K and P^T K P are symmetric, so the streams hold only the pairs of upper blocks
//   (a <= b), about half of all pairs; each lower block is then the transpose of its mirror
//   (an index per coarse block, found once).
//   Multithreading without write races: E's block rows are split into contiguous ranges of about
//   equal pair counts, one stream per range containing only the pairs whose destination row a is
//   in the range. Streams are walked in parallel; each destination block receives its terms in K's
//   block order whatever the number of streams, so the result is bit-identical for any thread
//   count.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mgelastic/tet/brc_matrix.hpp"
#include "mgelastic/tet/tet_hierarchy.hpp"

namespace mgelastic::tet {

// Pattern of P^T K P (values zero). Throws Error when P's fine size differs from K's block rows.
BlockRowMatrix<double> galerkin_pattern(const BlockRowMatrix<double>& fine, const Prolongation& p);

// coarse <- P^T fine P by Eq. 9 with binary search per term; `coarse` has galerkin_pattern's
// pattern (or a superset).
void galerkin_naive(const BlockRowMatrix<double>& fine, const Prolongation& p,
                    BlockRowMatrix<double>& coarse);

class GalerkinStream {
 public:
  // Encodes the product for the patterns of `fine` and `coarse` (coarse must hold every (a, b) of
  // galerkin_pattern). `streams` = number of destination partitions, 0: the OpenMP thread count.
  GalerkinStream(const BlockRowMatrix<double>& fine, const Prolongation& p,
                 const BlockRowMatrix<double>& coarse, int streams = 0);

  // coarse <- P^T fine P; fine and coarse must have the patterns given at construction.
  void update(const BlockRowMatrix<double>& fine, BlockRowMatrix<double>& coarse) const;

  int stream_count() const { return static_cast<int>(m_streams.size()); }
  std::size_t pair_count() const;
  // Bytes of the control and data streams (what Table 1's 15-132 MB measures).
  std::size_t memory_bytes() const;

  // The control encoding, exposed for tests: appends the bytes for one block of K with `pairs`
  // pairs (first byte fetches the block; continuation bytes beyond 127).
  static void encode_block(std::vector<std::uint8_t>& control, int pairs);

 private:
  struct Stream {
    int row_begin = 0, row_end = 0;  // destination block rows [row_begin, row_end) of E
    int first_block = 0;             // block of K fetched by the first control byte
    std::vector<std::uint8_t> control;
    std::vector<double> weights;
    std::vector<std::int32_t> destinations;
  };
  std::vector<Stream> m_streams;
  // Per coarse block (a, b): index of (b, a) when a > b (copied as its transpose), else -1.
  std::vector<int> m_mirror;
  int m_fine_blocks = 0;
  int m_coarse_blocks = 0;
};

}  // namespace mgelastic::tet
