#include "mgelastic/core/threads.hpp"

#include <omp.h>

#include <algorithm>

namespace mgelastic {

void set_thread_count(int n) {
  omp_set_num_threads(n > 0 ? n : omp_get_num_procs());
}

int thread_count() {
  return omp_get_max_threads();
}

std::ptrdiff_t interleaved_block(std::ptrdiff_t count) {
  constexpr std::ptrdiff_t kBlocksPerThread = 16;
  return std::max<std::ptrdiff_t>(1, count / (kBlocksPerThread * omp_get_max_threads()));
}

}  // namespace mgelastic
