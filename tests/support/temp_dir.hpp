#pragma once
// A fresh directory under the system temp dir for tests that write files, removed (with its
// contents) by the destructor.
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <system_error>

namespace mgelastic::test {

class TempDir {
 public:
  explicit TempDir(const std::string& prefix = "mgelastic") {
    std::random_device device;
    m_path = std::filesystem::temp_directory_path() /
             (prefix + "_" + std::to_string(device()) + "_" + std::to_string(device()));
    std::filesystem::create_directories(m_path);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(m_path, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return m_path; }
  // Writes `content` (bytes as they are) to `name` inside the directory; returns its path.
  std::filesystem::path write(const std::string& name, const std::string& content) const {
    const std::filesystem::path file = m_path / name;
    std::ofstream(file, std::ios::binary) << content;
    return file;
  }

 private:
  std::filesystem::path m_path;
};

}  // namespace mgelastic::test
