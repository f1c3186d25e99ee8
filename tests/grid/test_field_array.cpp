#include "mgelastic/grid/field_array.hpp"

#include <gtest/gtest.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "mgelastic/core/heap_policy.hpp"

namespace mgelastic::grid {
namespace {

constexpr std::size_t kLargeField = 8'000'000;  // 64 MB of doubles: mapped on its own

template <typename T>
bool all_zero(const FieldArray<T>& v) {
  return std::all_of(v.begin(), v.end(), [](T x) { return x == T(0); });
}

// Resident pages of [data, data + bytes), whole pages inside it only (mincore).
long resident_pages(const void* data, std::size_t bytes) {
  const auto page = static_cast<std::uintptr_t>(sysconf(_SC_PAGESIZE));
  const auto begin = (reinterpret_cast<std::uintptr_t>(data) + page - 1) & ~(page - 1);
  const auto end = (reinterpret_cast<std::uintptr_t>(data) + bytes) & ~(page - 1);
  if (end <= begin) return 0;
  std::vector<unsigned char> state((end - begin) / page);
  if (mincore(reinterpret_cast<void*>(begin), end - begin, state.data()) != 0) return -1;
  return std::count_if(state.begin(), state.end(), [](unsigned char s) { return s & 1; });
}

TEST(FieldArray, AllocateZeroedGivesZerosWhereValuesWere) {
  FieldArray<float> v(1000, 7.0f);
  allocate_zeroed(v, 1000);  // same size: resize() alone would keep the sevens
  ASSERT_EQ(v.size(), 1000u);
  EXPECT_TRUE(all_zero(v));
  std::fill(v.begin(), v.end(), 3.0f);
  allocate_zeroed(v, 10);
  allocate_zeroed(v, kLargeField);
  ASSERT_EQ(v.size(), kLargeField);
  EXPECT_TRUE(all_zero(v));
}

TEST(FieldArray, CopiesAndAssignmentsKeepTheirValues) {
  FieldArray<double> v(5, 2.5);
  FieldArray<double> copy = v;
  EXPECT_EQ(copy, v);
  v.assign(3, -1.0);
  EXPECT_EQ(v, FieldArray<double>(3, -1.0));
  EXPECT_EQ(copy, FieldArray<double>(5, 2.5));
}

// The point of the type: a large field costs no page until written (field_array.hpp).
TEST(FieldArray, AllocateZeroedWritesNoPage) {
  ASSERT_TRUE(restore_heap_release());  // large blocks mapped on their own, as in the CLI
  FieldArray<double> v;
  allocate_zeroed(v, kLargeField);
  const long resident = resident_pages(v.data(), kLargeField * sizeof(double));
  if (resident < 0) GTEST_SKIP() << "mincore is not available here";
  EXPECT_EQ(resident, 0) << "of " << kLargeField * sizeof(double) / 4096 << " pages";
  v[kLargeField / 2] = 1.0;  // one write maps at least one page (4 KiB, or 2 MiB on a huge page)
  EXPECT_GT(resident_pages(v.data(), kLargeField * sizeof(double)), 0);
}

}  // namespace
}  // namespace mgelastic::grid
