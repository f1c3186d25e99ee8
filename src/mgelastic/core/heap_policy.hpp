#pragma once
// How the process heap hands memory back to the OS.
//
// libsuperlu_dist (loaded with hypre, the benchmark baseline) switches glibc's malloc at load time
// to never mmap and never trim (mallopt(M_MMAP_MAX, 0), mallopt(M_TRIM_THRESHOLD, -1)). Every
// array the setup builds and frees then stays resident for the life of the process: at 128^3 the
// peak RSS was twice the solver's working set, and a 512^3 box could not fit its memory goal.

namespace mgelastic {

// Large blocks (>= 1 MiB) are mapped and unmapped on their own again, and free memory at the
// top of the heap beyond 2 MiB is trimmed. Call once at program start (the CLI and the Python
// module do), after the shared libraries have loaded. Returns false if glibc refused a setting.
bool restore_heap_release();

}  // namespace mgelastic
