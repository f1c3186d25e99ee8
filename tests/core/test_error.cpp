#include <gtest/gtest.h>

#include "mgelastic/core/error.hpp"

namespace mgelastic {

TEST(Error, MessageNamesFileLinePointerAndReason) {
  const Error error("expected a number", ErrorContext{.file = "a.obj", .line = 12, .pointer = ""});
  EXPECT_STREQ(error.what(), "a.obj:12: expected a number");
  const Error scene_error("must be positive", ErrorContext{.file = "s.json", .pointer = "/grid/h"});
  EXPECT_STREQ(scene_error.what(), "s.json: /grid/h: must be positive");
}

TEST(Error, RequireThrowsOnlyWhenConditionFails) {
  EXPECT_NO_THROW(require(true, "n", "unused"));
  EXPECT_THROW(require(false, "--n", "must be >= 8"), Error);
}

}  // namespace mgelastic
