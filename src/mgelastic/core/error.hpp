#pragma once
// One error type for everything a user can get wrong. The library throws it; it never exits or
// aborts on user input. The CLI maps it to a non-zero exit code and prints what().
#include <stdexcept>
#include <string>

namespace mgelastic {

// Where an error happened: a file (with optional line), a JSON pointer, a field or parameter name,
// an element or vertex index. Empty parts are omitted from the message.
struct ErrorContext {
  std::string file;
  long line = -1;
  std::string pointer;  // JSON pointer inside a scene file, or a parameter name
};

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& reason, ErrorContext context = {});
  const ErrorContext& context() const { return m_context; }
  const std::string& reason() const { return m_reason; }

 private:
  ErrorContext m_context;
  std::string m_reason;
};

// Formats "file:line: pointer: reason", leaving out what is unknown.
std::string format_error(const std::string& reason, const ErrorContext& context);

// Throws Error naming `parameter` and its value unless `condition` holds.
void require(bool condition, const std::string& parameter, const std::string& reason);

}  // namespace mgelastic
