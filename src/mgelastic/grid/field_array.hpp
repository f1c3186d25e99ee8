#pragma once
// The storage of a level's fields x, b and r: a std::vector whose memory comes zeroed from the
// allocator (calloc) and whose resize() leaves new elements as they are (default-initialized,
// no write) instead of writing zeros.
//
// Why: a field of an embedded body's level spans the body's bounding box, most of it dead
// (live_chunks.hpp). std::vector<T>::assign(n, 0) writes every page of it, and on a virtual
// machine each first write is a page fault of several microseconds: 2.2 s for the double
// solution level of the armadillo at 256 cells, most of it on pages released right after.
// calloc maps a large block fresh from the kernel (heap_policy.hpp: blocks of 1 MiB and more),
// already zero and with no page touched, so allocate_zeroed() below costs no page faults and
// the dead pages never hold memory.
//
// The catch: resize() into capacity that held values keeps those values. Fields are sized once,
// by allocate_zeroed() or assign_zeros_sparse() (live_chunks.hpp), which release the old storage
// first; nothing else grows them.
#include <cstdlib>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace mgelastic::grid {

template <typename T>
struct ZeroedAllocator {
  using value_type = T;

  ZeroedAllocator() = default;
  template <typename U>
  ZeroedAllocator(const ZeroedAllocator<U>&) noexcept {}

  T* allocate(std::size_t n) {
    void* p = std::calloc(n, sizeof(T));
    if (!p && n) throw std::bad_alloc();
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t) noexcept { std::free(p); }

  // Default construction writes nothing for trivial U: the element is the object calloc
  // created implicitly, zero (C++20 implicit object creation), not an indeterminate value.
  template <typename U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    if constexpr (!std::is_trivially_default_constructible_v<U>) ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }

  template <typename U>
  bool operator==(const ZeroedAllocator<U>&) const noexcept {
    return true;
  }
};

template <typename T>
using FieldArray = std::vector<T, ZeroedAllocator<T>>;

// v = n zeros in fresh storage, without writing it (see above).
template <typename T>
void allocate_zeroed(FieldArray<T>& v, std::size_t n) {
  static_assert(std::is_arithmetic_v<T>);
  FieldArray<T>().swap(v);  // release the old storage: its values would survive resize()
  v.reserve(n);
  v.resize(n);
}

}  // namespace mgelastic::grid
