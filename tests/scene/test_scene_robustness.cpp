// Regressions from fuzzing the scene loader (fuzz/fuzz_scene.cpp): JSON the parser rejects for
// other reasons than syntax, values that passed validation but could not be represented, and
// nesting that would overflow the stack are Errors naming the file and the JSON pointer.
#include <gtest/gtest.h>

#include <string>

#include "mgelastic/core/error.hpp"
#include "mgelastic/scene/scene.hpp"
#include "scene/scene_test_support.hpp"
#include "support/temp_dir.hpp"

namespace mgelastic::scene {
namespace {

// The parse error of a scene given as JSON text.
std::string text_error_of(const std::string& text) {
  return test::parse_error_of(nlohmann::json::parse(text));
}

// `depth` unions around a box.
std::string nested_union(int depth) {
  std::string open, close;
  for (int i = 0; i < depth; ++i) {
    open += R"({"union": [)";
    close += "]}";
  }
  return R"({"geometry": )" + open + R"({"box": {"size": [1, 1, 1]}})" + close + "}";
}

// Found by fuzz_scene: nlohmann::json throws out_of_range, not parse_error, for a number beyond
// double's range, and it escaped load_scene as a foreign exception.
TEST(SceneRobustness, NumberOverflowInJsonIsAnError) {
  test::TempDir dir;
  const auto path = dir.write("s.json", R"({"geometry": {"sphere": {"radius": 7e777777777}}})");
  try {
    load_scene(path);
    ADD_FAILURE() << "no mgelastic::Error thrown";
  } catch (const Error& e) {
    EXPECT_EQ(e.context().file, path.string());
    EXPECT_NE(e.reason().find("number overflow"), std::string::npos) << e.reason();
  }
}

// Integers are stored in int: 2^32 + 4 used to pass as >= 4 and wrap around to 4.
TEST(SceneRobustness, IntegerBeyondIntIsRejected) {
  EXPECT_EQ(text_error_of(
                R"({"geometry": {"sphere": {"radius": 1}}, "grid": {"resolution": 4294967300}})"),
            "scene.json: /grid/resolution: must be <= 2147483647 (got 4294967300)");
  EXPECT_EQ(text_error_of(
                R"({"geometry": {"sphere": {"radius": 1}}, "grid": {"resolution": 2147483647}})"),
            "");
}

TEST(SceneRobustness, CsgNestingIsBounded) {
  EXPECT_EQ(text_error_of(nested_union(64)), "");
  EXPECT_NE(text_error_of(nested_union(65)).find("shapes nested deeper than 64 CSG levels"),
            std::string::npos);
  // Deep enough to overflow the stack of the recursive validation without the bound.
  EXPECT_NE(text_error_of(nested_union(100000)).find("nested deeper"), std::string::npos);
}

}  // namespace
}  // namespace mgelastic::scene
