// A progress bar on stderr for long sweeps, redrawn in place when stderr is a terminal.
// Log lines go above it; without a terminal only the log lines are written.
#pragma once

#include <chrono>
#include <string>

namespace pfxbench {

class Progress {
 public:
  explicit Progress(double totalWork);
  void setLabel(const std::string& label);
  void advance(double work);
  void log(const std::string& line);
  void finish();

 private:
  void draw();
  void clear();

  double m_total;
  double m_done = 0;
  std::string m_label;
  bool m_terminal;
  std::chrono::steady_clock::time_point m_lastDraw;
};

}  // namespace pfxbench
