#pragma once
// The BLAS under SuiteSparse's factorizations runs on one thread.
//
// CHOLMOD's supernodal Cholesky and UMFPACK's LU spend their time in dense BLAS kernels (dgemm,
// dsyrk, dtrsm), so an optimized BLAS (Debian's OpenBLAS, scripts/install-deps.sh) makes the
// coarse factorizations several times faster than the reference BLAS. A multithreaded BLAS
// would split those kernels by the thread count and round differently for 1 and 2 threads, so
// results would depend on the thread count (Threads.ResultsDoNotDependOnThreadCount). The coarse
// matrices are small, and one thread is as fast there (armadillo at 128 cells: coarse
// factorization 0.21 s on one BLAS thread, 0.27 s on two).

namespace mgelastic {

// Sets the BLAS of the process to one thread if it is OpenBLAS or BLIS (found by symbol at run
// time, so any BLAS links); a no-op for the reference BLAS. Idempotent and thread-safe. Returns
// true if such a BLAS was found.
bool use_single_threaded_blas();

// While alive, the BLAS runs on one thread: use_single_threaded_blas() (OpenBLAS's pthreads
// build, BLIS), and OpenMP set to one thread, restored at the end of the scope (OpenBLAS's
// OpenMP build follows the OpenMP thread count at every call). Wraps each factorization and
// each solve with the factors; only outside parallel regions.
class SingleThreadedBlas {
 public:
  SingleThreadedBlas();
  ~SingleThreadedBlas();
  SingleThreadedBlas(const SingleThreadedBlas&) = delete;
  SingleThreadedBlas& operator=(const SingleThreadedBlas&) = delete;

 private:
  int m_openmp_threads;
};

}  // namespace mgelastic
