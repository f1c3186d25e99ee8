#pragma once
// Level arrays on 2 MiB pages. The band sweeps gather from a few cells of every lattice row
// near the boundary (one 4 KiB page per few rows), so with 4 KiB pages nearly every gather of
// a large level misses the TLB; transparent huge pages (madvise mode) cut the page count 512x.
// Advisory only: where the kernel declines, the arrays stay on ordinary pages.
#include <cstddef>
#include <vector>

namespace mgelastic::grid {

// Marks [data, data + bytes) for transparent huge pages (the 2 MiB-aligned part of it).
void advise_huge_pages(void* data, std::size_t bytes);

// v.assign(n, value) with the storage marked for huge pages before it is first touched.
template <typename T>
void assign_on_huge_pages(std::vector<T>& v, std::size_t n, const T& value) {
  v.clear();
  v.reserve(n);
  advise_huge_pages(v.data(), n * sizeof(T));
  v.assign(n, value);
}

}  // namespace mgelastic::grid
