#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
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

// Bitwise equality (distinguishes -0.0 from 0.0).
template <typename T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

// Mostly zero, as a lattice field outside a body: runs of every length, zero gaps of 1 to 12
// values (shorter than kNonzeroRunGap they stay inside a run), -0.0, both ends non-zero.
std::vector<double> sparse_field() {
  std::vector<double> v(5000, 0.0);
  v.front() = 1.5;
  v.back() = -2.0;
  std::size_t at = 10;
  for (int run = 1; at + 200 < v.size(); ++run) {
    for (int i = 0; i < run % 9 + 1; ++i) v[at++] = 0.25 * run + i;
    at += static_cast<std::size_t>(run % 12 + 1);
    if (run % 5 == 0) v[at++] = -0.0;
    at += 40;
  }
  return v;
}

TEST(Checkpoint, NonzeroRunsKeepEveryBitAndStoreOnlyTheRuns) {
  const std::vector<double> field = sparse_field();
  const std::vector<float> single{0.0f, 0.0f, 3.0f, -0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 7.0f};
  const std::vector<double> zeros(100, 0.0), empty;
  Checkpoint c = sample();
  c.add_nonzero_runs<double>("grid.x0", field);
  c.add_nonzero_runs<float>("grid.f", single);
  c.add_nonzero_runs<double>("grid.zeros", zeros);
  c.add_nonzero_runs<double>("grid.empty", empty);
  const Checkpoint back = parse_checkpoint(serialize_checkpoint(c), "run/checkpoint.mgck");
  // Read into storage that holds other values: every value is written, zeros included.
  std::vector<double> out(field.size(), 9.0);
  back.get_into<double>("grid.x0", out);
  EXPECT_TRUE(same_bits(out, field));
  std::vector<float> out_single(single.size(), 9.0f);
  back.get_into<float>("grid.f", out_single);
  EXPECT_TRUE(same_bits(out_single, single));
  std::vector<double> out_zeros(zeros.size(), 9.0), out_empty;
  back.get_into<double>("grid.zeros", out_zeros);
  EXPECT_TRUE(same_bits(out_zeros, zeros));
  back.get_into<double>("grid.empty", out_empty);
  // Only the runs are stored: far fewer values than the field has.
  std::size_t nonzero = 0;
  for (double x : field) nonzero += std::signbit(x) || x != 0.0;
  const std::size_t stored = back.get<double>("grid.x0").size();
  EXPECT_GE(stored, nonzero);
  EXPECT_LT(stored, field.size() / 4);
  EXPECT_EQ(back.get<double>("grid.zeros").size(), 0u);
  // Candidate ranges (a lattice's live chunks) that cover every non-zero value: the same field.
  const std::vector<std::array<std::size_t, 2>> ranges{{0, 2600}, {2600, 4000}, {4000, 5000}};
  Checkpoint ranged;
  ranged.add_nonzero_runs<double>("grid.x0", field, ranges);
  std::fill(out.begin(), out.end(), 9.0);
  ranged.get_into<double>("grid.x0", out);
  EXPECT_TRUE(same_bits(out, field));
  const std::vector<std::array<std::size_t, 2>> overlapping{{0, 2600}, {2500, 5000}};
  EXPECT_THROW(ranged.add_nonzero_runs<double>("grid.x1", field, overlapping), Error);
  // Arrays written densely (older checkpoints) read the same way.
  std::vector<double> dense(4, 9.0);
  back.get_into<double>("tet.positions", dense);
  EXPECT_TRUE(same_bits(dense, sample().get<double>("tet.positions")));
}

TEST(Checkpoint, DamagedOrMismatchedRunsAreRefused) {
  const std::vector<double> field = sparse_field();
  Checkpoint c;
  c.add_nonzero_runs<double>("grid.x0", field);
  std::vector<double> out(field.size() + 1);
  try {
    c.get_into<double>("grid.x0", out);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("this scene needs " + std::to_string(out.size())),
              std::string::npos)
        << e.what();
  }
  out.resize(field.size());
  // Swap the first two runs: out of order.
  std::vector<std::int64_t> runs = c.get<std::int64_t>("grid.x0.runs");
  ASSERT_GE(runs.size(), 5u);
  std::swap(runs[1], runs[3]);
  std::swap(runs[2], runs[4]);
  Checkpoint damaged;
  damaged.source = "run/checkpoint.mgck";
  damaged.add<double>("grid.x0", c.get<double>("grid.x0"));
  damaged.add<std::int64_t>("grid.x0.runs", runs);
  try {
    damaged.get_into<double>("grid.x0", out);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("run/checkpoint.mgck"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("is damaged"), std::string::npos) << e.what();
  }
}

TEST(Checkpoint, MissingFileIsAnError) {
  EXPECT_THROW(read_checkpoint("/nonexistent/checkpoint.mgck"), Error);
}

}  // namespace
}  // namespace mgelastic::io
