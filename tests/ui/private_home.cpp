// Linked into every UI test program (tests/ui/CMakeLists.txt): before main(), HOME becomes a
// folder of this process's own under the HOME ctest gives (HOME/run-PID), removed at exit.
// The studio keeps its settings and its autosave's recovery file under HOME; two test
// programs at once (ui.editor and ui.editor_offscreen of two concurrent ctest runs) would
// otherwise write and discard each other's recovery file. Programs a test starts (the
// studio, the CLI) inherit it.

#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>
#include <unistd.h>

namespace {

std::filesystem::path& privateHome() {
  static std::filesystem::path home;
  return home;
}

const bool kPrivateHome = [] {
  const char* base = std::getenv("HOME");
  if (!base || !*base)
    return false;
  const std::filesystem::path home = std::filesystem::path(base) / ("run-" + std::to_string(::getpid()));
  std::error_code error;
  std::filesystem::create_directories(home, error);
  if (error)
    return false;
  ::setenv("HOME", home.c_str(), 1);
  privateHome() = home;
  std::atexit([] {
    std::error_code ignored;
    std::filesystem::remove_all(privateHome(), ignored);
  });
  return true;
}();

} // namespace
