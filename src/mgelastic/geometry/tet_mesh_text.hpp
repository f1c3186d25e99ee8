#pragma once
// Internal helper of the tet mesh readers: a cursor over a whole file held in memory that hands
// out whitespace-separated tokens, whole records (one line, '#' comments stripped) and raw binary
// bytes, and always knows the line it stands on so every error can name file and line.
#include <cstddef>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "mgelastic/core/error.hpp"

namespace mgelastic::geometry::detail {

class TextCursor {
 public:
  // Reads the file; throws Error when it cannot be opened.
  explicit TextCursor(const std::filesystem::path& path);
  // For tests and in-memory data.
  TextCursor(std::string content, std::string source);

  const std::string& source() const { return m_source; }
  long line() const { return m_line; }
  bool at_end() const { return m_pos >= m_data.size(); }
  // Bytes not read yet.
  std::size_t remaining() const { return m_data.size() - m_pos; }
  // Error unless `count` items of at least `min_bytes` bytes each fit in the bytes left (a text
  // item of k tokens needs 2k bytes: digits and separators). Counts come from file headers: a
  // corrupt one must fail here, not in a huge allocation or a loop over nothing.
  void require_room(long count, std::size_t min_bytes, const std::string& what,
                    bool binary = false) const;

  // Next token; false at end of data. Tokens never cross lines' whitespace.
  bool next_token(std::string_view& token);
  // Next token or Error "unexpected end of file" mentioning `what`.
  std::string_view expect_token(const std::string& what);
  long expect_int(const std::string& what);
  double expect_double(const std::string& what);
  // Tokens of the next non-blank line ('#' starts a comment when strip_comments).
  bool next_record(std::vector<std::string_view>& tokens, bool strip_comments = true);

  // Moves to the end of the current line (for comments).
  void skip_rest_of_line();

  // Binary access (Gmsh binary sections): skips exactly one line ending first when asked.
  void skip_line_end();
  void read_bytes(void* destination, std::size_t count, const std::string& what);
  template <class T>
  T read_binary(const std::string& what) {
    T value;
    read_bytes(&value, sizeof(T), what);
    return value;
  }
  // Moves past the next occurrence of `marker` (e.g. "$EndEntities"); Error if absent.
  void skip_past(std::string_view marker);

  Error error(const std::string& reason) const;
  Error error_at(long line, const std::string& reason) const;
  // Errors inside binary data name the byte offset (a line number means nothing there).
  Error binary_error(const std::string& reason) const;

 private:
  void skip_space();

  std::string m_data;
  std::string m_source;
  std::size_t m_pos = 0;
  long m_line = 1;
};

long parse_int(std::string_view token, const TextCursor& cursor, const std::string& what);
double parse_double(std::string_view token, const TextCursor& cursor, const std::string& what);

}  // namespace mgelastic::geometry::detail
