#pragma once
// Raw-byte helpers shared by the lattice kernels' builders: hash keys made of a value's bytes
// (pattern / shape deduplication) and the memory a vector holds (working-set reports).
#include <cstddef>
#include <cstring>
#include <string>
#include <vector>

namespace mgelastic {

// Appends the object representation of `value` to `key` (equal values give equal keys).
template <typename T>
void append_bytes(std::string& key, const T& value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  key.append(bytes, sizeof(T));
}

// Bytes allocated by `v` (capacity, not size: what the process holds).
template <typename T, typename Allocator>
std::size_t vector_bytes(const std::vector<T, Allocator>& v) {
  return v.capacity() * sizeof(T);
}

}  // namespace mgelastic
