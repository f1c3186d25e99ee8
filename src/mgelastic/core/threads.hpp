#pragma once
// Thread-count control shared by every engine (OpenMP underneath).
#include <cstddef>

namespace mgelastic {

// Sets the number of worker threads; n <= 0 uses every processor.
void set_thread_count(int n);
int thread_count();

// Iterations per block for `schedule(static, block)` over `count` iterations that deals them out
// in 16 blocks per thread: each thread's share is spread over the whole range (the work of an
// embedded body's lattice is not spread evenly over its bounding box, and halves of the range
// left one thread with most of it) in blocks long enough for the hardware prefetchers.
std::ptrdiff_t interleaved_block(std::ptrdiff_t count);

}  // namespace mgelastic
