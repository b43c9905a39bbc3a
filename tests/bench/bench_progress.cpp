#include "bench_progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace pfxbench {

namespace {
constexpr int kBarWidth = 30;
}

Progress::Progress(double totalWork)
    : m_total(std::max(totalWork, 1.0)), m_terminal(isatty(STDERR_FILENO) != 0) {}

void Progress::setLabel(const std::string& label) {
  m_label = label;
  draw();
}

void Progress::advance(double work) {
  m_done += work;
  // Redrawing costs a system call; ten times a second is enough to look alive.
  const auto now = std::chrono::steady_clock::now();
  if (now - m_lastDraw > std::chrono::milliseconds(100)) draw();
}

void Progress::log(const std::string& line) {
  clear();
  std::fprintf(stderr, "%s\n", line.c_str());
  draw();
}

void Progress::finish() {
  clear();
  std::fflush(stderr);
}

void Progress::draw() {
  if (!m_terminal) return;
  m_lastDraw = std::chrono::steady_clock::now();
  const double fraction = std::min(1.0, m_done / m_total);
  const int filled = static_cast<int>(fraction * kBarWidth);
  std::fprintf(stderr, "\r[%.*s%*s] %3d%% %-50.50s", filled, "##############################",
               kBarWidth - filled, "", static_cast<int>(100 * fraction), m_label.c_str());
  std::fflush(stderr);
}

void Progress::clear() {
  if (m_terminal) std::fprintf(stderr, "\r%*s\r", kBarWidth + 58, "");
}

}  // namespace pfxbench
