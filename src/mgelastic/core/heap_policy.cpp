#include "mgelastic/core/heap_policy.hpp"

#include <malloc.h>

namespace mgelastic {

bool restore_heap_release() {
  // glibc's default mmap count; 1 MiB keeps small, short-lived temporaries on the heap (no page
  // faults per call) while every field array is mapped on its own.
  constexpr int max_mapped_blocks = 65536;
  constexpr int mapped_from_bytes = 1 << 20;
  constexpr int trim_above_bytes = 2 << 20;
  const bool ok = mallopt(M_MMAP_MAX, max_mapped_blocks) == 1 &&
                  mallopt(M_MMAP_THRESHOLD, mapped_from_bytes) == 1 &&
                  mallopt(M_TRIM_THRESHOLD, trim_above_bytes) == 1;
  malloc_trim(0);  // what was freed before the call
  return ok;
}

}  // namespace mgelastic
