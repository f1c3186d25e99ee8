#include "mgelastic/core/heap_policy.hpp"

#include <gtest/gtest.h>
#include <malloc.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>

namespace mgelastic {
namespace {

// VmRSS of /proc/self/status, bytes.
std::uint64_t resident_bytes() {
  std::ifstream status("/proc/self/status");
  std::string key;
  std::uint64_t kib = 0;
  while (status >> key) {
    if (key == "VmRSS:" && status >> kib) return kib * 1024;
    status.ignore(1 << 12, '\n');
  }
  return 0;
}

// Touches every page of a 64 MiB block, frees it, and returns how much of it stayed resident.
std::uint64_t resident_after_free() {
  constexpr std::size_t bytes = std::size_t(64) << 20;
  const std::uint64_t before = resident_bytes();
  {
    std::unique_ptr<char[]> block(new char[bytes]);
    std::memset(block.get(), 1, bytes);
    EXPECT_GE(resident_bytes(), before + bytes / 2);  // the block is really resident
  }
  const std::uint64_t after = resident_bytes();
  return after > before ? after - before : 0;
}

TEST(HeapPolicy, FreedBlocksGoBackToTheSystemAfterALibraryDisabledIt) {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  GTEST_SKIP() << "the sanitizer's allocator replaces glibc's malloc and ignores mallopt";
#endif
  // What libsuperlu_dist does at load time.
  ASSERT_EQ(mallopt(M_MMAP_MAX, 0), 1);
  ASSERT_EQ(mallopt(M_TRIM_THRESHOLD, -1), 1);
  EXPECT_GE(resident_after_free(), std::uint64_t(32) << 20);  // kept: the state to repair

  ASSERT_TRUE(restore_heap_release());
  EXPECT_LE(resident_after_free(), std::uint64_t(4) << 20);
}

}  // namespace
}  // namespace mgelastic
