#pragma once
// Thread-count control shared by every engine (OpenMP underneath).

namespace mgelastic {

// Sets the number of worker threads; n <= 0 uses every processor.
void set_thread_count(int n);
int thread_count();

}  // namespace mgelastic
