#pragma once
// Binary checkpoints of a run: everything later frames depend on, so that a run resumed from a
// checkpoint repeats an uninterrupted run bit for bit (same thread count).
//
// File layout (little-endian, every integer fixed-width):
//   header   8 bytes magic "MGECKPT\0", u32 format version, u64 payload bytes,
//            u64 FNV-1a (64 bit) hash of the payload bytes
//   payload  string engine, u64 scene fingerprint, i32 threads, i32 frame, f64 time,
//            u32 array count, then per array: string name, u8 scalar type, u64 length (elements),
//            length * sizeof(type) raw bytes
//   string   u32 byte count, then the bytes (no terminator)
// The state is a list of named arrays so engines add fields (a new carried vector) without a
// format change; readers ask for the arrays they need by name, type and length.
//
// Lattice fields are mostly zero (an embedded body fills a tenth of its bounding box: the
// armadillo at 256 cells holds 11.4 million lattice points per field for 1.3 million cells), so
// they are stored as their runs of non-zero values (add_nonzero_runs): array NAME holds the runs'
// values back to back, array NAME.runs (i64) the full length, then start and count of each run.
// get_into reads either form.
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace mgelastic::io {

inline constexpr std::uint32_t kCheckpointVersion = 1;
inline constexpr const char* kNonzeroRunsSuffix = ".runs";
inline constexpr std::size_t kNonzeroRunGap = 4;

enum class ScalarType : std::uint8_t { F64 = 1, F32 = 2, I64 = 3, I32 = 4, U8 = 5 };

std::size_t scalar_size(ScalarType type);
const char* scalar_name(ScalarType type);

template <typename T>
constexpr ScalarType scalar_type_of();
template <>
constexpr ScalarType scalar_type_of<double>() {
  return ScalarType::F64;
}
template <>
constexpr ScalarType scalar_type_of<float>() {
  return ScalarType::F32;
}
template <>
constexpr ScalarType scalar_type_of<std::int64_t>() {
  return ScalarType::I64;
}
template <>
constexpr ScalarType scalar_type_of<std::int32_t>() {
  return ScalarType::I32;
}
template <>
constexpr ScalarType scalar_type_of<std::uint8_t>() {
  return ScalarType::U8;
}

struct NamedArray {
  std::string name;
  ScalarType type = ScalarType::F64;
  std::uint64_t length = 0;      // elements
  std::vector<std::byte> bytes;  // length * scalar_size(type)
};

struct Checkpoint {
  std::string engine;                   // "grid" or "tet"
  std::uint64_t scene_fingerprint = 0;  // scene_fingerprint() of the scene that wrote it
  std::int32_t threads = 0;             // worker threads of the run that wrote it
  std::int32_t frame = -1;              // index of the last completed frame
  double time = 0.0;                    // simulated time of that frame, s
  std::vector<NamedArray> arrays;
  std::string source;  // the file it was read from (names it in errors); not stored
  // Arrays of an older snapshot whose storage add() reuses by name; not stored.
  std::vector<NamedArray> spare;

  template <typename T>
  void add(std::string name, std::span<const T> values) {
    // One pass over the bytes, into the storage of the spare array of that name when there is
    // one: a run snapshots its state after every frame (sim/run_checkpoints.hpp), and fresh
    // pages would be zeroed by the kernel each time.
    const auto* bytes = reinterpret_cast<const std::byte*>(values.data());
    NamedArray a = take_spare(std::move(name));
    a.type = scalar_type_of<T>();
    a.length = values.size();
    a.bytes.assign(bytes, bytes + values.size_bytes());
    arrays.push_back(std::move(a));
  }
  // `values` as its runs of non-zero values (see the layout above; zero gaps shorter than
  // kNonzeroRunGap values stay inside a run). Bit-exact: -0.0 counts as non-zero. T: float or
  // double.
  template <typename T>
  void add_nonzero_runs(std::string name, std::span<const T> values);
  // The same where the values outside `candidates` (ascending, disjoint [begin, end) ranges) are
  // known to be zero: those are not read (a lattice field's dead pages; reading one maps the zero
  // page, a page fault each, 0.6 s for the armadillo at 256 cells on a virtual machine).
  template <typename T>
  void add_nonzero_runs(std::string name, std::span<const T> values,
                        std::span<const std::array<std::size_t, 2>> candidates);
  // The array `name` as T; throws Error naming the file and the array when it is missing, has
  // another type, or (expected_length >= 0) another length.
  template <typename T>
  std::vector<T> get(std::string_view name, std::int64_t expected_length = -1) const {
    const NamedArray& a = find(name, scalar_type_of<T>(), expected_length);
    std::vector<T> values(a.length);
    if (a.length > 0) std::memcpy(values.data(), a.bytes.data(), a.bytes.size());
    return values;
  }
  // The array `name`, written by add() or add_nonzero_runs(), into `out`, whose length it must
  // have (the values outside the runs are set to zero; pages that hold zeros are only read).
  // Throws Error naming the file and the array when it is missing, damaged or of another type
  // or length. T: float or double.
  template <typename T>
  void get_into(std::string_view name, std::span<T> out) const;
  bool has(std::string_view name) const;

 private:
  NamedArray take_spare(std::string name);
  const NamedArray& find(std::string_view name, ScalarType type,
                         std::int64_t expected_length) const;
};

// FNV-1a, 64 bit.
std::uint64_t fnv1a64(std::span<const std::byte> bytes,
                      std::uint64_t hash = 14695981039346656037ull);
std::uint64_t fnv1a64(std::string_view text);

// The checkpoint as file bytes (header + payload), and back; parse_checkpoint throws Error naming
// `source` and the reason (not a checkpoint, unsupported version, truncated, checksum mismatch).
std::vector<std::byte> serialize_checkpoint(const Checkpoint& checkpoint);
Checkpoint parse_checkpoint(std::span<const std::byte> bytes, const std::string& source);

// Writes atomically (atomic_file.hpp): a crash while writing leaves the previous checkpoint.
void write_checkpoint(const std::filesystem::path& path, const Checkpoint& checkpoint);
Checkpoint read_checkpoint(const std::filesystem::path& path);

}  // namespace mgelastic::io
