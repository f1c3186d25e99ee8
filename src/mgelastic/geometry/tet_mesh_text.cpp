#include "mgelastic/geometry/tet_mesh_text.hpp"

#include <cctype>
#include <charconv>
#include <fstream>
#include <iterator>
#include <sstream>

namespace mgelastic::geometry::detail {

TextCursor::TextCursor(const std::filesystem::path& path) : m_source(path.string()) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open file", ErrorContext{m_source, -1, std::string()});
  std::ostringstream buffer;
  buffer << in.rdbuf();
  m_data = std::move(buffer).str();
}

TextCursor::TextCursor(std::string content, std::string source)
    : m_data(std::move(content)), m_source(std::move(source)) {}

void TextCursor::skip_space() {
  while (m_pos < m_data.size()) {
    const char c = m_data[m_pos];
    if (c == '\n') {
      ++m_line;
    } else if (c != ' ' && c != '\t' && c != '\r' && c != '\f' && c != '\v') {
      return;
    }
    ++m_pos;
  }
}

bool TextCursor::next_token(std::string_view& token) {
  skip_space();
  if (at_end()) return false;
  const std::size_t begin = m_pos;
  while (m_pos < m_data.size() && !std::isspace(static_cast<unsigned char>(m_data[m_pos]))) ++m_pos;
  token = std::string_view(m_data).substr(begin, m_pos - begin);
  return true;
}

std::string_view TextCursor::expect_token(const std::string& what) {
  std::string_view token;
  if (!next_token(token)) throw error("unexpected end of file (truncated?) while reading " + what);
  return token;
}

long TextCursor::expect_int(const std::string& what) {
  return parse_int(expect_token(what), *this, what);
}

double TextCursor::expect_double(const std::string& what) {
  return parse_double(expect_token(what), *this, what);
}

bool TextCursor::next_record(std::vector<std::string_view>& tokens, bool strip_comments) {
  tokens.clear();
  while (tokens.empty()) {
    skip_space();
    if (at_end()) return false;
    std::size_t end = m_data.find('\n', m_pos);
    if (end == std::string::npos) end = m_data.size();
    std::string_view line = std::string_view(m_data).substr(m_pos, end - m_pos);
    if (strip_comments) line = line.substr(0, line.find('#'));
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
      const std::size_t begin = i;
      while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
      if (i > begin) tokens.push_back(line.substr(begin, i - begin));
    }
    m_pos = end;  // the newline itself is counted by the next skip_space
    if (tokens.empty()) continue;
  }
  return true;
}

void TextCursor::skip_rest_of_line() {
  const std::size_t end = m_data.find('\n', m_pos);
  m_pos = end == std::string::npos ? m_data.size() : end;
}

void TextCursor::skip_line_end() {
  if (m_pos < m_data.size() && m_data[m_pos] == '\r') ++m_pos;
  if (m_pos < m_data.size() && m_data[m_pos] == '\n') {
    ++m_pos;
    ++m_line;
  }
}

void TextCursor::read_bytes(void* destination, std::size_t count, const std::string& what) {
  if (m_data.size() - m_pos < count)
    throw binary_error("unexpected end of file (truncated?) while reading " + what);
  std::memcpy(destination, m_data.data() + m_pos, count);
  m_pos += count;
}

void TextCursor::require_room(long count, std::size_t min_bytes, const std::string& what,
                              bool binary) const {
  // The last item may lack its trailing separator, hence the + 1.
  if (count >= 0 && static_cast<std::size_t>(count) <= (remaining() + 1) / min_bytes) return;
  const std::string reason = "the file cannot hold " + std::to_string(count) + " " + what + " (" +
                             std::to_string(remaining()) + " bytes left; corrupt count?)";
  throw binary ? binary_error(reason) : error(reason);
}

void TextCursor::skip_past(std::string_view marker) {
  const std::size_t found = m_data.find(marker, m_pos);
  if (found == std::string::npos)
    throw error("missing '" + std::string(marker) + "' (truncated file?)");
  for (std::size_t i = m_pos; i < found; ++i) m_line += m_data[i] == '\n' ? 1 : 0;
  m_pos = found + marker.size();
}

Error TextCursor::error(const std::string& reason) const {
  return error_at(m_line, reason);
}

Error TextCursor::error_at(long line, const std::string& reason) const {
  return Error(reason, ErrorContext{m_source, line, std::string()});
}

Error TextCursor::binary_error(const std::string& reason) const {
  return Error(reason, ErrorContext{m_source, -1, "byte " + std::to_string(m_pos)});
}

long parse_int(std::string_view token, const TextCursor& cursor, const std::string& what) {
  long value = 0;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (ec != std::errc() || end != token.data() + token.size())
    throw cursor.error("expected an integer for " + what + ", got '" + std::string(token) + "'");
  return value;
}

double parse_double(std::string_view token, const TextCursor& cursor, const std::string& what) {
  double value = 0.0;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (ec != std::errc() || end != token.data() + token.size())
    throw cursor.error("expected a number for " + what + ", got '" + std::string(token) + "'");
  return value;
}

}  // namespace mgelastic::geometry::detail
