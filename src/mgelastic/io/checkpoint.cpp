#include "mgelastic/io/checkpoint.hpp"

#include <algorithm>
#include <bit>
#include <fstream>
#include <type_traits>

#include "mgelastic/core/error.hpp"
#include "mgelastic/io/atomic_file.hpp"

namespace mgelastic::io {
namespace {

static_assert(std::endian::native == std::endian::little,
              "checkpoints store raw little-endian values");

constexpr char kMagic[8] = {'M', 'G', 'E', 'C', 'K', 'P', 'T', '\0'};
constexpr std::size_t kHeaderBytes = 8 + 4 + 8 + 8;

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

NamedArray Checkpoint::take_spare(std::string name) {
  NamedArray a;
  for (NamedArray& s : spare)
    if (s.name == name) {
      a = std::move(s);
      s.name.clear();  // used
      break;
    }
  a.name = std::move(name);
  return a;
}

namespace {

template <typename T>
bool is_zero(const T& value) {
  using Bits = std::conditional_t<sizeof(T) == 8, std::uint64_t, std::uint32_t>;
  return std::bit_cast<Bits>(value) == 0;
}

// The length, then (start, count) of the runs of non-zero values inside `candidates`, gaps of
// fewer than kNonzeroRunGap zeros merged.
template <typename T>
std::vector<std::int64_t> nonzero_runs(std::span<const T> values,
                                       std::span<const std::array<std::size_t, 2>> candidates) {
  std::vector<std::int64_t> runs{static_cast<std::int64_t>(values.size())};
  for (const auto& [begin, range_end] : candidates) {
    const std::size_t n = std::min(range_end, values.size());
    std::size_t i = begin;
    while (true) {
      while (i < n && is_zero(values[i])) ++i;
      if (i >= n) break;
      const std::size_t start = i;
      std::size_t end = i + 1;  // one past the run's last non-zero value
      for (std::size_t j = end; j < n && j - end < kNonzeroRunGap; ++j)
        if (!is_zero(values[j])) end = j + 1;
      runs.push_back(static_cast<std::int64_t>(start));
      runs.push_back(static_cast<std::int64_t>(end - start));
      i = end;
    }
  }
  return runs;
}

}  // namespace

template <typename T>
void Checkpoint::add_nonzero_runs(std::string name, std::span<const T> values) {
  const std::array<std::size_t, 2> everything{0, values.size()};
  add_nonzero_runs(std::move(name), values, std::span(&everything, 1));
}

template <typename T>
void Checkpoint::add_nonzero_runs(std::string name, std::span<const T> values,
                                  std::span<const std::array<std::size_t, 2>> candidates) {
  for (std::size_t c = 0; c < candidates.size(); ++c)
    if (candidates[c][0] > candidates[c][1] || (c > 0 && candidates[c][0] < candidates[c - 1][1]))
      throw Error("add_nonzero_runs: candidate ranges must be ascending and disjoint");
  std::vector<std::int64_t> runs = nonzero_runs(values, candidates);
  std::size_t stored = 0;
  for (std::size_t r = 1; r < runs.size(); r += 2) stored += static_cast<std::size_t>(runs[r + 1]);
  NamedArray data = take_spare(name);
  data.type = scalar_type_of<T>();
  data.length = stored;
  data.bytes.resize(stored * sizeof(T));
  std::byte* to = data.bytes.data();
  for (std::size_t r = 1; r < runs.size(); r += 2) {
    const std::size_t bytes = static_cast<std::size_t>(runs[r + 1]) * sizeof(T);
    std::memcpy(to, values.data() + runs[r], bytes);
    to += bytes;
  }
  arrays.push_back(std::move(data));
  add<std::int64_t>(name + kNonzeroRunsSuffix, runs);
}

template <typename T>
void Checkpoint::get_into(std::string_view name, std::span<T> out) const {
  const std::string runs_name = std::string(name) + kNonzeroRunsSuffix;
  if (!has(runs_name)) {
    const NamedArray& a = find(name, scalar_type_of<T>(), static_cast<std::int64_t>(out.size()));
    if (!out.empty()) std::memcpy(out.data(), a.bytes.data(), a.bytes.size());
    return;
  }
  const std::vector<std::int64_t> runs = get<std::int64_t>(runs_name);
  const NamedArray& data = find(name, scalar_type_of<T>(), -1);
  const auto damaged = [&](const std::string& why) {
    return Error("checkpoint array '" + runs_name + "' is damaged: " + why,
                 ErrorContext{.file = source});
  };
  if (runs.empty() || runs.size() % 2 == 0) throw damaged("it holds no length and run pairs");
  if (runs[0] != static_cast<std::int64_t>(out.size()))
    throw Error("checkpoint array '" + std::string(name) + "' has " + std::to_string(runs[0]) +
                    " values, this scene needs " + std::to_string(out.size()) +
                    " (a checkpoint of another mesh or resolution?)",
                ErrorContext{.file = source});
  const T* from = reinterpret_cast<const T*>(data.bytes.data());
  std::uint64_t used = 0;
  std::int64_t next = 0;  // first value not yet written
  const auto clear = [&](std::int64_t lo, std::int64_t hi) {
    for (std::int64_t k = lo; k < hi; ++k)
      if (!is_zero(out[static_cast<std::size_t>(k)])) out[static_cast<std::size_t>(k)] = T(0);
  };
  for (std::size_t r = 1; r < runs.size(); r += 2) {
    const std::int64_t start = runs[r], count = runs[r + 1];
    if (start < next || count <= 0 || count > runs[0] - start)
      throw damaged("run " + std::to_string(r / 2) + " is out of order or out of range");
    if (static_cast<std::uint64_t>(count) > data.length - used)
      throw damaged("its runs hold more values than array '" + std::string(name) + "'");
    clear(next, start);
    std::memcpy(out.data() + start, from + used, static_cast<std::size_t>(count) * sizeof(T));
    used += static_cast<std::uint64_t>(count);
    next = start + count;
  }
  if (used != data.length)
    throw damaged("its runs hold fewer values than array '" + std::string(name) + "'");
  clear(next, runs[0]);
}

template void Checkpoint::add_nonzero_runs<double>(std::string, std::span<const double>);
template void Checkpoint::add_nonzero_runs<float>(std::string, std::span<const float>);
template void Checkpoint::add_nonzero_runs<double>(std::string, std::span<const double>,
                                                   std::span<const std::array<std::size_t, 2>>);
template void Checkpoint::add_nonzero_runs<float>(std::string, std::span<const float>,
                                                  std::span<const std::array<std::size_t, 2>>);
template void Checkpoint::get_into<double>(std::string_view, std::span<double>) const;
template void Checkpoint::get_into<float>(std::string_view, std::span<float>) const;

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

namespace {

// The payload's pieces in file order: sink(data, bytes) for each.
template <typename Sink>
void emit_payload(const Checkpoint& c, Sink&& sink) {
  const auto put = [&](const auto& value) { sink(&value, sizeof value); };
  const auto put_string = [&](const std::string& text) {
    put(static_cast<std::uint32_t>(text.size()));
    sink(text.data(), text.size());
  };
  put_string(c.engine);
  put(c.scene_fingerprint);
  put(c.threads);
  put(c.frame);
  put(c.time);
  put(static_cast<std::uint32_t>(c.arrays.size()));
  for (const NamedArray& a : c.arrays) {
    put_string(a.name);
    put(static_cast<std::uint8_t>(a.type));
    put(a.length);
    sink(a.bytes.data(), a.bytes.size());
  }
}

struct PayloadFacts {
  std::uint64_t bytes = 0;
  std::uint64_t checksum = fnv1a64(std::span<const std::byte>());
};

PayloadFacts payload_facts(const Checkpoint& c) {
  PayloadFacts facts;
  emit_payload(c, [&](const void* data, std::size_t n) {
    facts.bytes += n;
    facts.checksum = fnv1a64(std::span(static_cast<const std::byte*>(data), n), facts.checksum);
  });
  return facts;
}

template <typename Sink>
void emit_header(const PayloadFacts& facts, Sink&& sink) {
  sink(kMagic, sizeof kMagic);
  sink(&kCheckpointVersion, sizeof kCheckpointVersion);
  sink(&facts.bytes, sizeof facts.bytes);
  sink(&facts.checksum, sizeof facts.checksum);
}

}  // namespace

std::vector<std::byte> serialize_checkpoint(const Checkpoint& c) {
  const PayloadFacts facts = payload_facts(c);
  std::vector<std::byte> file;
  file.reserve(kHeaderBytes + facts.bytes);
  const auto sink = [&](const void* data, std::size_t n) {
    const auto* from = static_cast<const std::byte*>(data);
    file.insert(file.end(), from, from + n);
  };
  emit_header(facts, sink);
  emit_payload(c, sink);
  return file;
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
  // Streamed from the arrays (the checksum first, in a pass of its own): no copy of a payload of
  // hundreds of megabytes.
  const PayloadFacts facts = payload_facts(checkpoint);
  write_file_atomically(
      path,
      [&](std::ostream& out) {
        const auto sink = [&](const void* data, std::size_t n) {
          out.write(static_cast<const char*>(data), static_cast<std::streamsize>(n));
        };
        emit_header(facts, sink);
        emit_payload(checkpoint, sink);
      },
      true);
}

Checkpoint read_checkpoint(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw Error("cannot open the checkpoint", ErrorContext{.file = path.string()});
  const std::streamoff size = in.tellg();
  std::vector<char> chars(size > 0 ? static_cast<std::size_t>(size) : 0);
  in.seekg(0);
  if (!in.read(chars.data(), static_cast<std::streamsize>(chars.size())))
    throw Error("cannot read the checkpoint", ErrorContext{.file = path.string()});
  return parse_checkpoint(std::as_bytes(std::span(chars.data(), chars.size())), path.string());
}

}  // namespace mgelastic::io
