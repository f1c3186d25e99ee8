#include "mgelastic/core/blas_threads.hpp"

#include <dlfcn.h>

#include <mutex>

#include <omp.h>

namespace mgelastic {
namespace {

using SetThreads = void (*)(int);

// The BLAS's "set number of threads" entry point, looked up among the loaded libraries.
SetThreads blas_thread_setter(const char* name) {
  return reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, name));
}

}  // namespace

bool use_single_threaded_blas() {
  static std::once_flag once;
  static bool found = false;
  std::call_once(once, [] {
    for (const char* name : {"openblas_set_num_threads", "bli_thread_set_num_threads"}) {
      if (SetThreads set = blas_thread_setter(name)) {
        set(1);
        found = true;
      }
    }
  });
  return found;
}

SingleThreadedBlas::SingleThreadedBlas() : m_openmp_threads(omp_get_max_threads()) {
  use_single_threaded_blas();
  omp_set_num_threads(1);
}

SingleThreadedBlas::~SingleThreadedBlas() {
  omp_set_num_threads(m_openmp_threads);
}

}  // namespace mgelastic
