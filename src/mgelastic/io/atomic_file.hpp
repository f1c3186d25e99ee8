#pragma once
// Atomic file output: contents go to `path.tmp`, are flushed, then renamed over `path`, so a
// reader (or a crash, or Ctrl-C) never sees a half-written file and earlier outputs stay valid.
#include <filesystem>
#include <functional>
#include <ostream>

namespace mgelastic::io {

// Creates missing parent directories; throws mgelastic::Error naming the path on failure.
void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(std::ostream&)>& write, bool binary = false);

}  // namespace mgelastic::io
