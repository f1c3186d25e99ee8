#include "mgelastic/core/error.hpp"

#include <sstream>

namespace mgelastic {

std::string format_error(const std::string& reason, const ErrorContext& context) {
  std::ostringstream message;
  if (!context.file.empty()) {
    message << context.file;
    if (context.line >= 0) message << ":" << context.line;
    message << ": ";
  }
  if (!context.pointer.empty()) message << context.pointer << ": ";
  message << reason;
  return message.str();
}

Error::Error(const std::string& reason, ErrorContext context)
    : std::runtime_error(format_error(reason, context)),
      m_context(std::move(context)),
      m_reason(reason) {}

void require(bool condition, const std::string& parameter, const std::string& reason) {
  if (!condition) throw Error(reason, ErrorContext{.pointer = parameter});
}

}  // namespace mgelastic
