#include "mgelastic/grid/live_chunks.hpp"

#include <sys/mman.h>
#include <unistd.h>

#include <numeric>

#include "mgelastic/grid/huge_pages.hpp"
#include "mgelastic/grid/level.hpp"

namespace mgelastic::grid {
namespace {

std::uintptr_t page_bytes() {
  static const auto bytes = static_cast<std::uintptr_t>(sysconf(_SC_PAGESIZE));
  return bytes;
}

}  // namespace

std::size_t LiveChunks::live_count() const {
  return static_cast<std::size_t>(std::accumulate(live.begin(), live.end(), std::size_t{0}));
}

template <int Dim>
LiveChunks find_live_chunks(const Lattice<Dim>& lattice, const VarCodes& codes) {
  const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(lattice.size());
  const std::ptrdiff_t row_length = lattice.padded(0);
  const std::ptrdiff_t rows = n / row_length;
  // Rows holding a variable, then their neighbours along the other axes.
  std::vector<std::uint8_t> holds(static_cast<std::size_t>(rows), 0);
  for (std::ptrdiff_t row = 0; row < rows; ++row) {
    const VarCode* c = codes.data() + row * row_length;  // 0: no variable (var_codes.hpp)
    holds[static_cast<std::size_t>(row)] =
        std::any_of(c, c + row_length, [](VarCode code) { return code != 0; });
  }
  std::vector<std::uint8_t> live_row = holds;
  for (std::ptrdiff_t row = 0; row < rows; ++row) {
    if (!holds[static_cast<std::size_t>(row)]) continue;
    for (int a = 1; a < Dim; ++a) {
      const std::ptrdiff_t step = lattice.stride(a) / row_length;
      if (row - step >= 0) live_row[static_cast<std::size_t>(row - step)] = 1;
      if (row + step < rows) live_row[static_cast<std::size_t>(row + step)] = 1;
    }
  }
  LiveChunks chunks;
  chunks.live.assign(static_cast<std::size_t>((n + kLiveChunk - 1) / kLiveChunk), 0);
  for (std::ptrdiff_t row = 0; row < rows; ++row) {
    if (!live_row[static_cast<std::size_t>(row)]) continue;
    const std::ptrdiff_t begin = row * row_length, end = begin + row_length;
    for (std::ptrdiff_t c = begin / kLiveChunk; c * kLiveChunk < end; ++c)
      chunks.live[static_cast<std::size_t>(c)] = 1;
  }
  if (chunks.live_count() == chunks.live.size()) {
    chunks.live.clear();
    return chunks;
  }
  chunks.row_length = row_length;
  chunks.span.assign(static_cast<std::size_t>(rows), {0, 0});
  for (std::ptrdiff_t row = 0; row < rows; ++row) {
    if (!holds[static_cast<std::size_t>(row)]) continue;
    const VarCode* c = codes.data() + row * row_length;
    const auto has = [](VarCode code) { return code != 0; };
    const VarCode* first = std::find_if(c, c + row_length, has);
    const VarCode* last = std::find_if(std::make_reverse_iterator(c + row_length),
                                       std::make_reverse_iterator(first), has)
                              .base();
    chunks.span[static_cast<std::size_t>(row)] = {static_cast<std::int32_t>(first - c),
                                                  static_cast<std::int32_t>(last - c)};
  }
  return chunks;
}

namespace {

constexpr std::uintptr_t kHugePage = std::uintptr_t{1} << 21;

// Whether the page at p (of the array of n elements T at base) overlaps a live chunk.
template <typename T>
bool live_page(std::uintptr_t base, std::size_t n, const LiveChunks& live, std::uintptr_t p) {
  const auto e0 = static_cast<std::ptrdiff_t>((p - base) / sizeof(T));
  const auto e1 = static_cast<std::ptrdiff_t>(
      std::min<std::uintptr_t>(p + page_bytes() - base, n * sizeof(T)) / sizeof(T));
  return live.any_live(e0, e1);
}

// Whether the 2 MiB range at h (aligned, inside the array) stays on a huge page, dead pages
// and all: with 4 KiB pages the kernels' strided streams miss the TLB (on this virtual machine
// the bunny at 256 ran 24 % slower per cycle on 4 KiB pages throughout), so only ranges that
// are mostly dead give their pages back.
template <typename T>
bool huge_range(std::uintptr_t base, std::size_t n, const LiveChunks& live, std::uintptr_t h) {
  const std::uintptr_t page = page_bytes();
  std::size_t live_pages = 0;
  for (std::uintptr_t p = h; p < h + kHugePage; p += page)
    live_pages += live_page<T>(base, n, live, p);
  return live_pages * page >= kHugePage / 2;
}

// Calls dead(p0, p1) for each maximal stretch [p0, p1) of whole pages of [base, base + n
// elements) that overlaps no live chunk and lies outside the huge ranges.
template <typename T, typename F>
void for_each_dead_stretch(std::uintptr_t base, std::size_t n, const LiveChunks& live, F&& dead) {
  const std::uintptr_t page = page_bytes();
  const std::uintptr_t end = base + n * sizeof(T);
  std::uintptr_t run = 0;  // start of the current stretch, 0 = none
  std::uintptr_t p = (base + page - 1) & ~(page - 1);
  std::uintptr_t range = 0;  // the 2 MiB range of p, and whether it is huge
  bool huge = false;
  for (; p + page <= end; p += page) {
    if ((p & ~(kHugePage - 1)) != range) {
      range = p & ~(kHugePage - 1);
      huge = range >= base && range + kHugePage <= end && huge_range<T>(base, n, live, range);
    }
    if (!huge && !live_page<T>(base, n, live, p)) {
      if (run == 0) run = p;
    } else if (run != 0) {
      dead(run, p);
      run = 0;
    }
  }
  if (run != 0) dead(run, p);
}

}  // namespace

template <typename T>
std::vector<std::pair<std::uintptr_t, std::uintptr_t>> released_stretches(const FieldArray<T>& v,
                                                                          const LiveChunks& live) {
  std::vector<std::pair<std::uintptr_t, std::uintptr_t>> stretches;
  if (live.all_live() || v.empty()) return stretches;
  for_each_dead_stretch<T>(
      reinterpret_cast<std::uintptr_t>(v.data()), v.size(), live,
      [&](std::uintptr_t p0, std::uintptr_t p1) { stretches.emplace_back(p0, p1); });
  return stretches;
}

template <typename T>
std::size_t released_bytes(const FieldArray<T>& v, const LiveChunks& live) {
  std::size_t bytes = 0;
  for (const auto& [p0, p1] : released_stretches(v, live)) bytes += p1 - p0;
  return bytes;
}

template <typename T>
void assign_zeros_sparse(FieldArray<T>& v, std::size_t n, const LiveChunks& live) {
  // Fresh zeroed storage that no write has touched (field_array.hpp): pages are mapped where a
  // pass first writes, so the dead ones hold no memory. No huge page may hold a dead page (where
  // the system's THP mode is "always" too): a partly written huge page takes its whole 2 MiB, and
  // khugepaged would fill it. So: no huge pages, then huge pages on the huge ranges.
  allocate_zeroed(v, n);
  if (live.all_live()) {
    advise_huge_pages(v.data(), n * sizeof(T));
    return;
  }
  const auto base = reinterpret_cast<std::uintptr_t>(v.data());
  const std::uintptr_t page = page_bytes();
  const std::uintptr_t end = base + n * sizeof(T);
  const std::uintptr_t first_page = (base + page - 1) & ~(page - 1);
#ifdef MADV_NOHUGEPAGE
  if (end > first_page)
    madvise(reinterpret_cast<void*>(first_page), end - first_page, MADV_NOHUGEPAGE);
#endif
  for (std::uintptr_t h = (base + kHugePage - 1) & ~(kHugePage - 1); h + kHugePage <= end;
       h += kHugePage)
    if (huge_range<T>(base, n, live, h)) advise_huge_pages(reinterpret_cast<void*>(h), kHugePage);
  // Where calloc handed out heap memory (below the mmap threshold, heap_policy.hpp) it wrote its
  // zeros: the dead pages go back.
  for_each_dead_stretch<T>(base, n, live, [](std::uintptr_t p0, std::uintptr_t p1) {
    madvise(reinterpret_cast<void*>(p0), p1 - p0, MADV_DONTNEED);
  });
}

namespace {

// Whether the bytes [p0, p1) (whole pages) are all zero: -0.0 is not, as releasing it would
// turn it into +0.0.
bool zero_bytes(std::uintptr_t p0, std::uintptr_t p1) {
  const auto* word = reinterpret_cast<const std::uint64_t*>(p0);
  const auto* end = reinterpret_cast<const std::uint64_t*>(p1);
  std::uint64_t any = 0;
  for (; word < end; ++word) any |= *word;
  return any == 0;
}

}  // namespace

template <typename T>
std::vector<std::pair<std::uintptr_t, std::uintptr_t>> release_zero_pages(FieldArray<T>& v,
                                                                          const LiveChunks& live) {
  std::vector<std::pair<std::uintptr_t, std::uintptr_t>> released;
  if (v.empty()) return released;
  const auto base = reinterpret_cast<std::uintptr_t>(v.data());
  const std::size_t n = v.size();
  const std::uintptr_t page = page_bytes();
  const std::uintptr_t end = base + n * sizeof(T);
  const auto release = [&](std::uintptr_t p0, std::uintptr_t p1) {
    madvise(reinterpret_cast<void*>(p0), p1 - p0, MADV_DONTNEED);
    if (!released.empty() && released.back().second == p0)
      released.back().second = p1;
    else
      released.emplace_back(p0, p1);
  };
  std::uintptr_t p = (base + page - 1) & ~(page - 1);
  while (p + page <= end) {
    const std::uintptr_t range = p & ~(kHugePage - 1);
    const bool inside = range >= base && range + kHugePage <= end;
    if (inside && (live.all_live() || huge_range<T>(base, n, live, range))) {
      if (zero_bytes(range, range + kHugePage)) release(range, range + kHugePage);
      p = range + kHugePage;
      continue;
    }
    // Outside huge ranges a page that overlaps no live chunk is released already.
    if ((live.all_live() || live_page<T>(base, n, live, p)) && zero_bytes(p, p + page))
      release(p, p + page);
    p += page;
  }
  return released;
}

template LiveChunks find_live_chunks<2>(const Lattice<2>&, const VarCodes&);
template LiveChunks find_live_chunks<3>(const Lattice<3>&, const VarCodes&);
template std::vector<std::pair<std::uintptr_t, std::uintptr_t>> release_zero_pages<float>(
    FieldArray<float>&, const LiveChunks&);
template std::vector<std::pair<std::uintptr_t, std::uintptr_t>> release_zero_pages<double>(
    FieldArray<double>&, const LiveChunks&);
template void assign_zeros_sparse<float>(FieldArray<float>&, std::size_t, const LiveChunks&);
template void assign_zeros_sparse<double>(FieldArray<double>&, std::size_t, const LiveChunks&);
template std::size_t released_bytes<float>(const FieldArray<float>&, const LiveChunks&);
template std::size_t released_bytes<double>(const FieldArray<double>&, const LiveChunks&);
template std::vector<std::pair<std::uintptr_t, std::uintptr_t>> released_stretches<float>(
    const FieldArray<float>&, const LiveChunks&);
template std::vector<std::pair<std::uintptr_t, std::uintptr_t>> released_stretches<double>(
    const FieldArray<double>&, const LiveChunks&);

}  // namespace mgelastic::grid
