#include "progress.hpp"

#include <unistd.h>

#include <cstdio>

namespace mgelastic::app {

Progress::Progress(std::string label, int total)
    : m_label(std::move(label)), m_total(total), m_terminal(isatty(fileno(stdout)) != 0) {}

void Progress::update(int done, const std::string& status) {
  if (!m_terminal) {
    std::printf("%s %d/%d  %s\n", m_label.c_str(), done, m_total, status.c_str());
    std::fflush(stdout);
    return;
  }
  constexpr int width = 30;
  const int filled = m_total > 0 ? width * done / m_total : width;
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.resize(width, '.');
  // \r returns to the line start, \033[K clears what a longer earlier status left behind.
  std::printf("\r%s [%s] %d/%d  %s\033[K", m_label.c_str(), bar.c_str(), done, m_total,
              status.c_str());
  std::fflush(stdout);
  m_open = true;
}

void Progress::finish() {
  if (m_terminal && m_open) std::printf("\n");
  m_open = false;
}

}  // namespace mgelastic::app
