#pragma once
// Shared by the fuzz targets. The readers take file paths, so each fuzz input is written to a file
// of this process (in /dev/shm when there is one: no disk traffic at thousands of inputs per
// second). The file is removed when the fuzzer exits normally.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <system_error>

#include "mgelastic/core/error.hpp"

namespace mgelastic::fuzz {

class InputFile {
 public:
  // `name` is the file name, e.g. "input.obj"; the folder is unique to this process.
  explicit InputFile(const std::string& name) {
    std::error_code ec;
    std::filesystem::path root = "/dev/shm";
    if (!std::filesystem::is_directory(root, ec)) root = std::filesystem::temp_directory_path();
    m_dir = root / ("mgelastic_fuzz_" + std::to_string(::getpid()));
    std::filesystem::create_directories(m_dir);
    m_path = m_dir / name;
  }
  ~InputFile() {
    std::error_code ec;
    std::filesystem::remove_all(m_dir, ec);
  }
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;

  const std::filesystem::path& path() const { return m_path; }

  // Replaces the file's content with `bytes`; returns the path.
  const std::filesystem::path& write(std::string_view bytes) const {
    std::ofstream out(m_path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return m_path;
  }

 private:
  std::filesystem::path m_dir;
  std::filesystem::path m_path;
};

inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// A rejected input is the expected outcome; MGELASTIC_FUZZ_VERBOSE=1 prints why (to check that
// seeds are accepted, or what a mutation broke).
inline void rejected(const Error& error) {
  static const bool verbose = std::getenv("MGELASTIC_FUZZ_VERBOSE") != nullptr;
  if (verbose) std::fprintf(stderr, "rejected: %s\n", error.what());
}

}  // namespace mgelastic::fuzz
