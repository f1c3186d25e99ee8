#pragma once
// Progress of a run over frames: on a terminal, one self-rewriting bar line with the latest
// status; otherwise (pipes, logs, CI) one plain line per update so logs stay greppable.
#include <string>

namespace mgelastic::app {

class Progress {
 public:
  Progress(std::string label, int total);
  // `done` of `total` finished; `status` says how the last one went.
  void update(int done, const std::string& status);
  // Ends the bar line (terminal) so later output starts on a fresh line.
  void finish();

 private:
  std::string m_label;
  int m_total;
  bool m_terminal;
  bool m_open = false;
};

}  // namespace mgelastic::app
