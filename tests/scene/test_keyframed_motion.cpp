#include <gtest/gtest.h>

#include <cmath>

#include "mgelastic/core/error.hpp"
#include "mgelastic/scene/keyframed_motion.hpp"
#include "mgelastic/scene/scene.hpp"
#include "scene/scene_test_support.hpp"
#include "support/tolerances.hpp"

namespace mgelastic::scene {
namespace {

nlohmann::json keyframed_scene() {
  return nlohmann::json::parse(R"({
    "geometry": {"box": {"size": [1, 0.2, 0.2]}},
    "constraints": [{"region": {"box": {"center": [0.5, 0, 0], "size": [0.1, 1, 1]}},
                     "motion": "keyframed", "pivot": [0.5, 0, 0],
                     "keyframes": [{"time": 0},
                                   {"time": 1, "translate": [0.2, 0, 0],
                                    "rotate_axis": [1, 0, 0], "rotate_degrees": 90}]}]})");
}

using test::parse_error_of;

TEST(KeyframedMotion, FixedMotionIsIdentity) {
  const KeyframedMotion fixed;
  const Eigen::Vector3d x(0.3, -1, 2);
  EXPECT_TRUE(fixed.is_fixed());
  EXPECT_EQ(fixed.position(x, 5.0), x);
}

TEST(KeyframedMotion, InterpolatesTranslationLinearlyAndRotationBySlerp) {
  const Scene s = parse_scene(keyframed_scene(), "scene.json", ".");
  const KeyframedMotion& m = s.constraints[0].motion;
  const Eigen::Vector3d x(0.5, 0, 1);  // 1 from the pivot along z
  // Halfway: 45 degrees about x through the pivot, half the translation.
  const Eigen::Vector3d half = m.position(x, 0.5);
  const double r = std::sqrt(0.5);
  EXPECT_NEAR((half - Eigen::Vector3d(0.6, -r, r)).norm(), 0.0, 1e-12);
  // Beyond the last key the last pose holds; before the first, the first.
  EXPECT_NEAR((m.position(x, 3.0) - Eigen::Vector3d(0.7, -1, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((m.position(x, -1.0) - x).norm(), 0.0, 1e-12);
}

TEST(KeyframedMotion, RigidAtEveryTime) {
  const Scene s = parse_scene(keyframed_scene(), "scene.json", ".");
  const KeyframedMotion& m = s.constraints[0].motion;
  const Eigen::Vector3d a(0.1, 0.2, 0.3), b(-0.4, 0.5, 0.9);
  for (double t : {0.1, 0.37, 0.8})
    EXPECT_NEAR((m.position(a, t) - m.position(b, t)).norm(), (a - b).norm(), 1e-12);
}

TEST(KeyframedMotion, NonIncreasingTimesAreRejectedWithPointer) {
  auto d = keyframed_scene();
  d["constraints"][0]["keyframes"][1]["time"] = 0;
  EXPECT_NE(
      parse_error_of(d).find("scene.json: /constraints/0/keyframes/1/time: keyframe times must "
                             "increase strictly"),
      std::string::npos)
      << parse_error_of(d);
}

TEST(KeyframedMotion, KeyframedRegionWithoutKeysIsRejected) {
  auto d = keyframed_scene();
  d["constraints"][0]["keyframes"] = nlohmann::json::array();
  EXPECT_NE(
      parse_error_of(d).find("/constraints/0/keyframes: a keyframed region needs at least one"),
      std::string::npos);
}

TEST(KeyframedMotion, KeysOnAFixedRegionAreRejected) {
  auto d = keyframed_scene();
  d["constraints"][0]["motion"] = "fixed";
  EXPECT_NE(parse_error_of(d).find("/constraints/0/keyframes: keyframes need"), std::string::npos);
}

}  // namespace
}  // namespace mgelastic::scene
