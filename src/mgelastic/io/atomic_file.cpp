#include "mgelastic/io/atomic_file.hpp"

#include <fstream>
#include <system_error>

#include "mgelastic/core/error.hpp"

namespace mgelastic::io {

void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(std::ostream&)>& write, bool binary) {
  std::error_code ec;
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path(), ec);
  if (ec)
    throw Error("cannot create the directory: " + ec.message(),
                ErrorContext{.file = path.parent_path().string()});
  std::filesystem::path temporary = path;
  temporary += ".tmp";
  try {
    std::ofstream out(temporary, binary ? std::ios::binary : std::ios::out);
    if (!out) throw Error("cannot open for writing", ErrorContext{.file = temporary.string()});
    write(out);
    out.flush();
    if (!out) throw Error("write failed (disk full?)", ErrorContext{.file = temporary.string()});
  } catch (...) {
    std::filesystem::remove(temporary, ec);  // the previous file at `path` stays untouched
    throw;
  }
  std::filesystem::rename(temporary, path, ec);
  if (ec)
    throw Error("cannot rename into place: " + ec.message(), ErrorContext{.file = path.string()});
}

}  // namespace mgelastic::io
