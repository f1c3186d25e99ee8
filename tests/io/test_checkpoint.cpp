#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <vector>

#include "mgelastic/core/error.hpp"
#include "mgelastic/io/checkpoint.hpp"
#include "support/temp_dir.hpp"

namespace mgelastic::io {
namespace {

Checkpoint sample() {
  Checkpoint c;
  c.engine = "tet";
  c.scene_fingerprint = 0x0123456789abcdefull;
  c.threads = 2;
  c.frame = 7;
  c.time = 8.0 / 30.0;
  const std::vector<double> positions{0.1, -2.5e-300, std::numeric_limits<double>::max(), -0.0};
  const std::vector<std::int64_t> steps{42};
  const std::vector<std::uint8_t> flags{1, 0, 255};
  const std::vector<float> empty;
  c.add<double>("tet.positions", positions);
  c.add<std::int64_t>("tet.steps", steps);
  c.add<std::uint8_t>("flags", flags);
  c.add<float>("empty", empty);
  return c;
}

// Expects parse_checkpoint to throw an Error whose message names the file and contains `reason`.
void expect_refused(const std::vector<std::byte>& bytes, const std::string& reason) {
  try {
    parse_checkpoint(bytes, "run/checkpoint.mgck");
    FAIL() << "accepted a bad checkpoint, expected: " << reason;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("run/checkpoint.mgck"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
  }
}

TEST(Checkpoint, RoundTripThroughAFileKeepsEveryBit) {
  const test::TempDir dir("mgelastic_ckpt");
  const Checkpoint original = sample();
  write_checkpoint(dir.path() / "c.mgck", original);
  const Checkpoint read = read_checkpoint(dir.path() / "c.mgck");
  EXPECT_EQ(read.engine, "tet");
  EXPECT_EQ(read.scene_fingerprint, original.scene_fingerprint);
  EXPECT_EQ(read.threads, 2);
  EXPECT_EQ(read.frame, 7);
  EXPECT_EQ(read.time, original.time);  // exact: raw bits
  ASSERT_EQ(read.arrays.size(), 4u);
  for (std::size_t i = 0; i < read.arrays.size(); ++i) {
    EXPECT_EQ(read.arrays[i].name, original.arrays[i].name);
    EXPECT_EQ(read.arrays[i].type, original.arrays[i].type);
    EXPECT_EQ(read.arrays[i].bytes, original.arrays[i].bytes);
  }
  const std::vector<double> positions = read.get<double>("tet.positions", 4);
  EXPECT_EQ(positions[1], -2.5e-300);
  EXPECT_TRUE(std::signbit(positions[3]));
  EXPECT_EQ(read.get<std::int64_t>("tet.steps").at(0), 42);
  EXPECT_TRUE(read.get<float>("empty").empty());
  EXPECT_EQ(serialize_checkpoint(read), serialize_checkpoint(original));
}

TEST(Checkpoint, EveryFlippedPayloadByteIsDetected) {
  const std::vector<std::byte> good = serialize_checkpoint(sample());
  // Header bytes 20..27 hold the checksum; from 28 on every byte is payload.
  for (std::size_t i = 28; i < good.size(); ++i) {
    std::vector<std::byte> bad = good;
    bad[i] ^= std::byte{0x10};
    EXPECT_THROW(parse_checkpoint(bad, "x"), Error) << "byte " << i;
  }
  std::vector<std::byte> bad = good;
  bad[good.size() / 2] ^= std::byte{0x01};
  expect_refused(bad, "checksum mismatch");
}

TEST(Checkpoint, TruncationIsDetectedAtEveryLength) {
  const std::vector<std::byte> good = serialize_checkpoint(sample());
  for (std::size_t n = 0; n < good.size(); ++n)
    EXPECT_THROW(parse_checkpoint(std::span(good).first(n), "x"), Error) << n << " bytes";
  expect_refused(std::vector<std::byte>(good.begin(), good.end() - 3), "truncated");
  expect_refused(std::vector<std::byte>(good.begin(), good.begin() + 12), "truncated");
}

TEST(Checkpoint, OtherVersionsAndOtherFilesAreRefused) {
  std::vector<std::byte> bytes = serialize_checkpoint(sample());
  bytes[8] = std::byte{kCheckpointVersion + 1};  // u32 version after the 8 magic bytes
  expect_refused(bytes, "format version 2 is not supported");
  const std::string text = "{\"geometry\": {}}";
  expect_refused(
      std::vector<std::byte>(reinterpret_cast<const std::byte*>(text.data()),
                             reinterpret_cast<const std::byte*>(text.data()) + text.size()),
      "not a mgelastic checkpoint");
}

TEST(Checkpoint, ArraysAreCheckedByNameTypeAndLength) {
  Checkpoint c = parse_checkpoint(serialize_checkpoint(sample()), "run/checkpoint.mgck");
  EXPECT_THROW(c.get<double>("tet.velocities"), Error);
  EXPECT_THROW(c.get<float>("tet.positions"), Error);
  try {
    c.get<double>("tet.positions", 5);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("has 4 values, this scene needs 5"), std::string::npos)
        << e.what();
  }
}

TEST(Checkpoint, Fnv1aMatchesTheReferenceVectors) {
  // Published FNV-1a 64 test vectors.
  EXPECT_EQ(fnv1a64(""), 0xcbf29ce484222325ull);
  EXPECT_EQ(fnv1a64("a"), 0xaf63dc4c8601ec8cull);
  EXPECT_EQ(fnv1a64("foobar"), 0x85944171f73967e8ull);
}

TEST(Checkpoint, MissingFileIsAnError) {
  EXPECT_THROW(read_checkpoint("/nonexistent/checkpoint.mgck"), Error);
}

}  // namespace
}  // namespace mgelastic::io
