#pragma once
// One updating line on stderr for long commands (export, batch): "stage  45%  detail",
// rewritten in place ("\r", then erase to the end of the line) and cut to the terminal's
// width so that it never wraps. Only where stderr is a terminal and the user asked for
// neither --quiet nor --json: a pipe, a log file or a farm's capture gets nothing extra.
// Thread-safe: batch jobs on several threads report through one line.

#include <chrono>
#include <mutex>
#include <string>
#include <string_view>

namespace mlod::cli {

class TerminalProgress {
public:
  // Shows the line when `wanted` (neither --quiet nor --json) and stderr is a terminal.
  explicit TerminalProgress(bool wanted);
  ~TerminalProgress(); // clears the line
  TerminalProgress(const TerminalProgress&) = delete;
  TerminalProgress& operator=(const TerminalProgress&) = delete;

  bool active() const { return m_active; }
  // fraction in [0, 1], or < 0 for a stage without a measure (no percent shown). Redraws at
  // most every 50 ms unless the stage changes or the fraction reaches 1.
  void show(std::string_view stage, double fraction, std::string_view detail = {});
  // Erases the line, so what is printed next starts on a clean one.
  void clear();

private:
  bool m_active = false;
  std::mutex m_mutex;
  std::string m_stage;
  std::chrono::steady_clock::time_point m_last{};
  bool m_shown = false;
};

} // namespace mlod::cli
