#pragma once
// STREAM triad (McCalpin): a[i] = b[i] + s * c[i] over three double arrays far larger than the
// caches, OpenMP-parallel with the current thread count (threads.hpp), each thread touching
// first the part it later streams. Bandwidth = 3 * 8 bytes per element / seconds of the best
// repetition (write-allocate traffic not counted, as STREAM reports it). The roofline of the
// V-cycle (grid/cycle_roofline.hpp) divides each phase's achieved bandwidth by this.
#include <cstddef>

namespace mgelastic {

struct TriadOptions {
  std::size_t bytes_per_array = std::size_t(64) << 20;  // 64 MiB, 8 Mi doubles
  int repetitions = 5;
};

// Best bandwidth over the repetitions, GB/s (1e9 bytes).
double stream_triad_gb_per_s(const TriadOptions& options = {});

}  // namespace mgelastic
