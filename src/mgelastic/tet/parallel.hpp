#pragma once
// When the tet kernels go parallel. An OpenMP region costs a fork/join (microseconds, far more
// when the cores are shared and idle threads spin); loops over fewer items than this run serially
// so small meshes, and the many small steps of tests, do not pay it. Used as
// `#pragma omp parallel for if (count >= kMinParallelItems)` (or kMinParallelElements).

namespace mgelastic::tet {

// Light items (a vertex's 3-vector, one block row of a product).
inline constexpr int kMinParallelItems = 4096;
// Heavy items (an element: rotation fit, 16 rotated blocks, 12x12 force product).
inline constexpr int kMinParallelElements = 256;

}  // namespace mgelastic::tet
