#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <vector>

#include "mgelastic/grid/huge_pages.hpp"

namespace mgelastic::grid {
namespace {

// The arrays span several 2 MiB pages at an arbitrary offset from a huge-page boundary.
constexpr std::size_t kLarge = 3'000'000;

TEST(HugePages, AssignedArrayHoldsTheValue) {
  std::vector<float> v{1.0f, 2.0f};
  assign_on_huge_pages(v, kLarge, 1.5f);
  ASSERT_EQ(v.size(), kLarge);
  EXPECT_TRUE(std::all_of(v.begin(), v.end(), [](float x) { return x == 1.5f; }));
  assign_on_huge_pages(v, std::size_t{5}, -2.0f);  // smaller than one huge page
  EXPECT_EQ(v, std::vector<float>(5, -2.0f));
}

// The advice may move pages but must never discard their contents.
TEST(HugePages, AdviceKeepsTheContents) {
  std::vector<double> v(kLarge);
  std::iota(v.begin(), v.end(), 0.0);
  advise_huge_pages(v.data(), v.size() * sizeof(double));
  advise_huge_pages(v.data() + 1, 100);  // below one huge page: nothing to do
  for (std::size_t k = 0; k < v.size(); ++k) ASSERT_EQ(v[k], static_cast<double>(k)) << k;
}

}  // namespace
}  // namespace mgelastic::grid
