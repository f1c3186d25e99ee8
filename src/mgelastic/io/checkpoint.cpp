#include "mgelastic/io/checkpoint.hpp"

#include <bit>
#include <fstream>
#include <iterator>

#include "mgelastic/core/error.hpp"
#include "mgelastic/io/atomic_file.hpp"

namespace mgelastic::io {
namespace {

static_assert(std::endian::native == std::endian::little,
              "checkpoints store raw little-endian values");

constexpr char kMagic[8] = {'M', 'G', 'E', 'C', 'K', 'P', 'T', '\0'};
constexpr std::size_t kHeaderBytes = 8 + 4 + 8 + 8;

class Writer {
 public:
  template <typename T>
  void put(T value) {
    raw(&value, sizeof value);
  }
  void put_string(const std::string& s) {
    put(static_cast<std::uint32_t>(s.size()));
    raw(s.data(), s.size());
  }
  void raw(const void* data, std::size_t n) {
    const std::size_t at = m_bytes.size();
    m_bytes.resize(at + n);
    if (n > 0) std::memcpy(m_bytes.data() + at, data, n);
  }
  std::vector<std::byte>& bytes() { return m_bytes; }

 private:
  std::vector<std::byte> m_bytes;
};

// Reads from the payload; every read checks the remaining length, so a truncated or corrupted
// file fails with a message instead of reading past the end.
class Reader {
 public:
  Reader(std::span<const std::byte> bytes, const std::string& source)
      : m_bytes(bytes), m_source(source) {}
  template <typename T>
  T get(const char* what) {
    T value;
    raw(&value, sizeof value, what);
    return value;
  }
  std::string get_string(const char* what) {
    const auto n = get<std::uint32_t>(what);
    std::string s(n, '\0');
    raw(s.data(), n, what);
    return s;
  }
  void raw(void* out, std::size_t n, const char* what) {
    if (n > m_bytes.size() - m_offset)
      throw Error(std::string("corrupted checkpoint: the payload ends inside ") + what,
                  ErrorContext{.file = m_source});
    if (n > 0) std::memcpy(out, m_bytes.data() + m_offset, n);
    m_offset += n;
  }
  std::size_t remaining() const { return m_bytes.size() - m_offset; }

 private:
  std::span<const std::byte> m_bytes;
  const std::string& m_source;
  std::size_t m_offset = 0;
};

bool known_type(std::uint8_t t) {
  return t >= static_cast<std::uint8_t>(ScalarType::F64) &&
         t <= static_cast<std::uint8_t>(ScalarType::U8);
}

}  // namespace

std::size_t scalar_size(ScalarType type) {
  switch (type) {
    case ScalarType::F64:
    case ScalarType::I64:
      return 8;
    case ScalarType::F32:
    case ScalarType::I32:
      return 4;
    case ScalarType::U8:
      break;
  }
  return 1;
}

const char* scalar_name(ScalarType type) {
  switch (type) {
    case ScalarType::F64:
      return "f64";
    case ScalarType::F32:
      return "f32";
    case ScalarType::I64:
      return "i64";
    case ScalarType::I32:
      return "i32";
    case ScalarType::U8:
      break;
  }
  return "u8";
}

bool Checkpoint::has(std::string_view name) const {
  for (const NamedArray& a : arrays)
    if (a.name == name) return true;
  return false;
}

const NamedArray& Checkpoint::find(std::string_view name, ScalarType type,
                                   std::int64_t expected_length) const {
  for (const NamedArray& a : arrays) {
    if (a.name != name) continue;
    if (a.type != type)
      throw Error("checkpoint array '" + a.name + "' holds " + scalar_name(a.type) + ", expected " +
                      scalar_name(type),
                  ErrorContext{.file = source});
    if (expected_length >= 0 && a.length != static_cast<std::uint64_t>(expected_length))
      throw Error("checkpoint array '" + a.name + "' has " + std::to_string(a.length) +
                      " values, this scene needs " + std::to_string(expected_length) +
                      " (a checkpoint of another mesh or resolution?)",
                  ErrorContext{.file = source});
    return a;
  }
  throw Error("checkpoint has no array '" + std::string(name) + "' (written by another engine?)",
              ErrorContext{.file = source});
}

std::uint64_t fnv1a64(std::span<const std::byte> bytes, std::uint64_t hash) {
  for (std::byte b : bytes) {
    hash ^= static_cast<std::uint64_t>(b);
    hash *= 1099511628211ull;
  }
  return hash;
}

std::uint64_t fnv1a64(std::string_view text) {
  return fnv1a64(std::as_bytes(std::span(text.data(), text.size())));
}

std::vector<std::byte> serialize_checkpoint(const Checkpoint& c) {
  Writer payload;
  payload.put_string(c.engine);
  payload.put(c.scene_fingerprint);
  payload.put(c.threads);
  payload.put(c.frame);
  payload.put(c.time);
  payload.put(static_cast<std::uint32_t>(c.arrays.size()));
  for (const NamedArray& a : c.arrays) {
    payload.put_string(a.name);
    payload.put(static_cast<std::uint8_t>(a.type));
    payload.put(a.length);
    payload.raw(a.bytes.data(), a.bytes.size());
  }
  Writer file;
  file.raw(kMagic, sizeof kMagic);
  file.put(kCheckpointVersion);
  file.put(static_cast<std::uint64_t>(payload.bytes().size()));
  file.put(fnv1a64(payload.bytes()));
  file.raw(payload.bytes().data(), payload.bytes().size());
  return std::move(file.bytes());
}

Checkpoint parse_checkpoint(std::span<const std::byte> bytes, const std::string& source) {
  const ErrorContext where{.file = source};
  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    throw Error("not a mgelastic checkpoint (bad magic bytes)", where);
  if (bytes.size() < kHeaderBytes)
    throw Error(
        "truncated checkpoint: " + std::to_string(bytes.size()) + " bytes, shorter than the header",
        where);
  Reader header(bytes.first(kHeaderBytes), source);
  char magic[8];
  header.raw(magic, sizeof magic, "magic");
  const auto version = header.get<std::uint32_t>("the version");
  if (version != kCheckpointVersion)
    throw Error("checkpoint format version " + std::to_string(version) +
                    " is not supported (this build reads version " +
                    std::to_string(kCheckpointVersion) + ")",
                where);
  const auto payload_bytes = header.get<std::uint64_t>("the payload size");
  const auto checksum = header.get<std::uint64_t>("the checksum");
  const std::span<const std::byte> payload = bytes.subspan(kHeaderBytes);
  if (payload.size() != payload_bytes)
    throw Error("truncated or padded checkpoint: the header announces " +
                    std::to_string(payload_bytes) + " payload bytes, the file has " +
                    std::to_string(payload.size()),
                where);
  if (fnv1a64(payload) != checksum)
    throw Error("corrupted checkpoint: checksum mismatch (the file was modified or damaged)",
                where);

  Reader in(payload, source);
  Checkpoint c;
  c.source = source;
  c.engine = in.get_string("the engine name");
  c.scene_fingerprint = in.get<std::uint64_t>("the scene fingerprint");
  c.threads = in.get<std::int32_t>("the thread count");
  c.frame = in.get<std::int32_t>("the frame index");
  c.time = in.get<double>("the time");
  const auto count = in.get<std::uint32_t>("the array count");
  for (std::uint32_t i = 0; i < count; ++i) {
    NamedArray a;
    a.name = in.get_string("an array name");
    const auto type = in.get<std::uint8_t>("an array type");
    if (!known_type(type))
      throw Error("corrupted checkpoint: array '" + a.name + "' has unknown scalar type " +
                      std::to_string(type),
                  where);
    a.type = static_cast<ScalarType>(type);
    a.length = in.get<std::uint64_t>("an array length");
    if (a.length > in.remaining() / scalar_size(a.type))
      throw Error("corrupted checkpoint: array '" + a.name + "' is longer than the file", where);
    a.bytes.resize(a.length * scalar_size(a.type));
    in.raw(a.bytes.data(), a.bytes.size(), "an array");
    c.arrays.push_back(std::move(a));
  }
  if (in.remaining() != 0) throw Error("corrupted checkpoint: bytes after the last array", where);
  return c;
}

void write_checkpoint(const std::filesystem::path& path, const Checkpoint& checkpoint) {
  const std::vector<std::byte> bytes = serialize_checkpoint(checkpoint);
  write_file_atomically(
      path,
      [&](std::ostream& out) {
        out.write(reinterpret_cast<const char*>(bytes.data()),
                  static_cast<std::streamsize>(bytes.size()));
      },
      true);
}

Checkpoint read_checkpoint(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open the checkpoint", ErrorContext{.file = path.string()});
  const std::vector<char> chars((std::istreambuf_iterator<char>(in)),
                                std::istreambuf_iterator<char>());
  return parse_checkpoint(std::as_bytes(std::span(chars.data(), chars.size())), path.string());
}

}  // namespace mgelastic::io
