#pragma once
// Wall-clock timing of solver phases (seconds, steady clock).
#include <chrono>

namespace mgelastic {

class Timer {
 public:
  Timer() : m_start(std::chrono::steady_clock::now()) {}
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
  }
  void restart() { m_start = std::chrono::steady_clock::now(); }

 private:
  std::chrono::steady_clock::time_point m_start;
};

}  // namespace mgelastic
