#include "cli/terminal_progress.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sys/ioctl.h>
#include <unistd.h>

namespace mlod::cli {

namespace {

int terminalColumns() {
  winsize size{};
  if (::ioctl(STDERR_FILENO, TIOCGWINSZ, &size) == 0 && size.ws_col > 0)
    return size.ws_col;
  return 80;
}

// The first `columns` characters of `text` (UTF-8: never cut inside a character).
std::string fit(const std::string& text, int columns) {
  std::size_t bytes = 0;
  int used = 0;
  while (bytes < text.size() && used < columns) {
    ++bytes;
    while (bytes < text.size() && (static_cast<unsigned char>(text[bytes]) & 0xC0) == 0x80)
      ++bytes;
    ++used;
  }
  return text.substr(0, bytes);
}

} // namespace

TerminalProgress::TerminalProgress(bool wanted) : m_active(wanted && ::isatty(STDERR_FILENO) == 1) {}

TerminalProgress::~TerminalProgress() {
  clear();
}

void TerminalProgress::show(std::string_view stage, double fraction, std::string_view detail) {
  if (!m_active)
    return;
  const std::lock_guard<std::mutex> lock(m_mutex);
  const auto now = std::chrono::steady_clock::now();
  if (stage == m_stage && m_shown && fraction < 1.0 && now - m_last < std::chrono::milliseconds(50))
    return;
  m_stage = std::string(stage);
  m_last = now;
  std::string line(stage);
  if (fraction >= 0.0) {
    char percent[16];
    std::snprintf(percent, sizeof percent, " %3d%%", static_cast<int>(std::floor(100.0 * std::min(fraction, 1.0))));
    line += percent;
  }
  if (!detail.empty()) {
    line += "  ";
    line += detail;
  }
  line = fit(line, terminalColumns() - 1);
  std::fprintf(stderr, "\r%s\033[K", line.c_str());
  std::fflush(stderr);
  m_shown = true;
}

void TerminalProgress::clear() {
  if (!m_active)
    return;
  const std::lock_guard<std::mutex> lock(m_mutex);
  if (!m_shown)
    return;
  std::fprintf(stderr, "\r\033[K");
  std::fflush(stderr);
  m_shown = false;
  m_stage.clear();
}

} // namespace mlod::cli
