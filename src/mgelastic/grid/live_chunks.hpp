#pragma once
// Memory that follows an embedded body instead of its bounding box (issue 24; the first step
// towards a block-sparse lattice). A level's fields x, b and r span the padded box of
// lattice.hpp, but most of an embedded body's box is far from every variable: there the values
// stay zero and no kernel reads or writes them. Those stretches of the arrays are handed back to
// the operating system (madvise MADV_DONTNEED: the pages read as zero and hold no memory until
// written again), and the passes over whole arrays skip them.
//
// Unit: chunks of kLiveChunk consecutive flat indices. A lattice row (every x of one y, z) is
// live when it or a row next to it along another axis holds a variable that is not INACTIVE in
// some field: the row-wise kernels write whole stretches of such rows and of their neighbour
// rows (zero deltas included). A chunk is live when it overlaps a live row, and an array's 4 KiB
// page is released when every chunk it overlaps is dead. Invariant: the fields are zero in dead
// chunks, so skipping a zero fill there changes nothing.
//
// On the armadillo at 256 cells, 49 % of the finest level's float pages hold a variable (18 %
// of its points). Pages are stretches of whole lattice rows, and 2 MiB ranges that are at least
// half live stay on huge pages (the kernels' strided streams need them), so the fields shrink
// by ~40 % there, where the tiles of issue 24 item 4 would follow the body closer.
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "mgelastic/core/threads.hpp"
#include "mgelastic/grid/field_array.hpp"
#include "mgelastic/grid/lattice.hpp"

namespace mgelastic::grid {

class VarCodes;

inline constexpr std::ptrdiff_t kLiveChunk = 512;

struct LiveChunks {
  std::vector<std::uint8_t> live;  // per chunk, 1 = live; empty = every chunk live
  // Per storage row (flat index / row_length): the x offsets [first, end) from its first to its
  // last point that holds a variable, {0, 0} where none; empty when every chunk is live. An
  // embedded body's live chunks are whole rows, about twice the points of the spans (the
  // armadillo at 256 cells: 5.9 M against 2.9 M on the finest level). The prolongation, which
  // computes the interpolated correction point by point, visits the spans alone (row_span);
  // the first step towards storing only them (layout_census.hpp: row ranges). Passes that are
  // bound by their pages rather than their points (the residuals, the refinement) gained
  // nothing from it.
  std::vector<std::array<std::int32_t, 2>> span;
  std::ptrdiff_t row_length = 0;

  bool all_live() const { return live.empty(); }
  // Whether [begin, end) overlaps a live chunk.
  bool any_live(std::ptrdiff_t begin, std::ptrdiff_t end) const {
    if (live.empty()) return end > begin;
    for (std::ptrdiff_t c = begin / kLiveChunk; c * kLiveChunk < end; ++c)
      if (live[static_cast<std::size_t>(c)]) return true;
    return false;
  }
  std::size_t live_count() const;
};

// The live chunks of a lattice whose variables `codes` describes (var_codes.hpp); all live
// (empty) when no chunk is dead.
template <int Dim>
LiveChunks find_live_chunks(const Lattice<Dim>& lattice, const VarCodes& codes);

// Calls visit(lo, hi) for the part [lo, hi) of each live chunk inside [begin, end), in order.
template <typename Visit>
void for_each_live_chunk(const LiveChunks& live, std::ptrdiff_t begin, std::ptrdiff_t end,
                         Visit&& visit) {
  for (std::ptrdiff_t c = begin / kLiveChunk; c * kLiveChunk < end; ++c)
    if (live.all_live() || live.live[static_cast<std::size_t>(c)])
      visit(std::max(begin, c * kLiveChunk), std::min(end, (c + 1) * kLiveChunk));
}

// The variable span [first, end) of the storage row that starts at flat index `row_begin`, as
// x offsets; the whole row [0, row_length) where the level keeps no spans.
inline std::array<int, 2> row_span(const LiveChunks& live, std::ptrdiff_t row_begin,
                                   int row_length) {
  if (live.span.empty()) return {0, row_length};
  const auto& span = live.span[static_cast<std::size_t>(row_begin / live.row_length)];
  return {span[0], span[1]};
}

// The live chunks of an array of n values as ascending [begin, end) ranges, neighbors joined:
// what a reader of the whole array must look at (checkpoints, io::Checkpoint::add_nonzero_runs).
inline std::vector<std::array<std::size_t, 2>> live_ranges(const LiveChunks& live, std::size_t n) {
  std::vector<std::array<std::size_t, 2>> ranges;
  for_each_live_chunk(live, 0, static_cast<std::ptrdiff_t>(n),
                      [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
                        const auto begin = static_cast<std::size_t>(lo);
                        const auto end = static_cast<std::size_t>(hi);
                        if (!ranges.empty() && ranges.back()[1] == begin)
                          ranges.back()[1] = end;
                        else
                          ranges.push_back({begin, end});
                      });
  return ranges;
}

// Zeroes [begin, end) of v except its dead chunks (which hold zeros already).
template <typename T>
void zero_live(T* v, std::ptrdiff_t begin, std::ptrdiff_t end, const LiveChunks& live) {
  for_each_live_chunk(live, begin, end, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
    std::fill(v + lo, v + hi, T(0));
  });
}

// visit(lo, hi) for every live chunk [lo, hi) of an array of n values, chunks spread over the
// threads (visits must be independent): whole-lattice passes that skip the dead chunks, whose
// reads would each fault in a zero page.
// Chunks go to the threads in interleaved blocks (threads.hpp: the live chunks of an embedded
// body are not spread evenly over its bounding box).
template <typename Visit>
void parallel_for_each_live_chunk(const LiveChunks& live, std::ptrdiff_t n, Visit&& visit) {
  const std::ptrdiff_t block = interleaved_block((n + kLiveChunk - 1) / kLiveChunk);
#pragma omp parallel for schedule(static, block)
  for (std::ptrdiff_t lo = 0; lo < n; lo += kLiveChunk) {
    const std::ptrdiff_t hi = std::min(lo + kLiveChunk, n);
    if (live.any_live(lo, hi)) visit(lo, hi);
  }
}

// Zeroes the live chunks of a whole array, in parallel.
template <typename T>
void zero_live(FieldArray<T>& v, const LiveChunks& live) {
  T* data = v.data();
  parallel_for_each_live_chunk(
      live, static_cast<std::ptrdiff_t>(v.size()),
      [&](std::ptrdiff_t lo, std::ptrdiff_t hi) { std::fill(data + lo, data + hi, T(0)); });
}

// zero_live that writes only the live chunks holding a nonzero: pages of a right-hand side that
// release_zero_pages handed back stay without memory where they were zero (reads map none).
// On all threads (the Krylov solve clears whole levels).
template <typename T>
void zero_live_where_nonzero(FieldArray<T>& v, const LiveChunks& live) {
  T* data = v.data();
  parallel_for_each_live_chunk(
      live, static_cast<std::ptrdiff_t>(v.size()), [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
        if (std::any_of(data + lo, data + hi, [](T value) { return value != T(0); }))
          std::fill(data + lo, data + hi, T(0));
      });
}

// Whether v holds only zeros (its dead chunks do by the invariant above; reads map no memory).
template <typename T>
bool zero_where_live(const FieldArray<T>& v, const LiveChunks& live) {
  bool zero = true;
  for_each_live_chunk(
      live, 0, static_cast<std::ptrdiff_t>(v.size()), [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
        zero = zero &&
               std::all_of(v.begin() + lo, v.begin() + hi, [](T value) { return value == T(0); });
      });
  return zero;
}

// dst = src (converted to dst's type) for arrays of one level: where the sizes match only the
// live chunks are copied (src is zero in the dead ones, by the invariant above), so dst's
// released pages stay released.
template <typename Dst, typename Src>
void assign_live(Dst& dst, const Src& src, const LiveChunks& live) {
  if (dst.size() != src.size()) {
    dst.assign(src.begin(), src.end());
    return;
  }
  for_each_live_chunk(live, 0, static_cast<std::ptrdiff_t>(src.size()),
                      [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
                        std::copy(src.begin() + lo, src.begin() + hi, dst.begin() + lo);
                      });
}
template <typename Dst, typename Src, std::size_t N>
void assign_live(std::array<Dst, N>& dst, const std::array<Src, N>& src, const LiveChunks& live) {
  for (std::size_t f = 0; f < N; ++f) assign_live(dst[f], src[f], live);
}

// packed = the live chunks of v one after the other: all that v holds beyond zeros. Reuses
// packed's storage (a solve's start state is packed on every solve).
template <typename T>
void pack_live_into(const FieldArray<T>& v, const LiveChunks& live, FieldArray<T>& packed) {
  if (live.all_live()) {
    packed.assign(v.begin(), v.end());
    return;
  }
  packed.clear();
  packed.reserve(live.live_count() * kLiveChunk);
  for_each_live_chunk(live, 0, static_cast<std::ptrdiff_t>(v.size()),
                      [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
                        packed.insert(packed.end(), v.begin() + lo, v.begin() + hi);
                      });
}

template <typename T>
FieldArray<T> pack_live(const FieldArray<T>& v, const LiveChunks& live) {
  FieldArray<T> packed;
  pack_live_into(v, live, packed);
  return packed;
}

// v's live chunks from pack_live's result (the dead ones are zero already).
template <typename T>
void unpack_live(const FieldArray<T>& packed, FieldArray<T>& v, const LiveChunks& live) {
  auto from = packed.begin();
  for_each_live_chunk(live, 0, static_cast<std::ptrdiff_t>(v.size()),
                      [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
                        std::copy(from, from + (hi - lo), v.begin() + lo);
                        from += hi - lo;
                      });
}

// v = n zeros, the pages of released_stretches never written (huge pages elsewhere).
template <typename T>
void assign_zeros_sparse(FieldArray<T>& v, std::size_t n, const LiveChunks& live);

// The address stretches [begin, end) of v's pages that assign_zeros_sparse released: pages that
// overlap no live chunk, outside the 2 MiB ranges that stay on huge pages (those with at least
// half of their pages live). Every pass keeps them released (the memory accounting's
// assumption; tests/grid/test_live_chunks.cpp checks it against the page table).
template <typename T>
std::vector<std::pair<std::uintptr_t, std::uintptr_t>> released_stretches(const FieldArray<T>& v,
                                                                          const LiveChunks& live);
template <typename T>
std::size_t released_bytes(const FieldArray<T>& v, const LiveChunks& live);

// Hands back the pages of v (a field laid out by assign_zeros_sparse with the same `live`) that
// hold only zero bytes and that released_stretches keeps: a whole 2 MiB range where the field is on
// a huge page (a partly released huge page would keep its memory), single 4 KiB pages elsewhere.
// They read as zero and hold no memory until written. For right-hand sides, which a load leaves
// zero in whole fields (gravity along y: b of u_x, u_z and p). Returns the released stretches
// (disjoint from released_stretches(v, live)).
template <typename T>
std::vector<std::pair<std::uintptr_t, std::uintptr_t>> release_zero_pages(FieldArray<T>& v,
                                                                          const LiveChunks& live);

}  // namespace mgelastic::grid
