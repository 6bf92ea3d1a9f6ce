#pragma once
// Runs `motionlod` with arguments and captures what it printed and its exit status.

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace mlod::test {

struct CliRun {
  int status = -1; // exit status; 128 + signal when killed by one
  std::string out;
  std::string err;
};

CliRun runMotionlod(const std::vector<std::string>& arguments);
// The same, stopped (SIGTERM, then SIGKILL 2 s later) after `timeoutSeconds`: a run that
// could hang (a FIFO, a kill) must not hang the test. A stopped run has status 124 or 137.
CliRun runMotionlod(const std::vector<std::string>& arguments, int timeoutSeconds);

// In a child process after fork() (its descriptors set up by the caller): becomes
// `PROGRAM ARGS` (execProgram) or `motionlod ARGS`; exits 127 if that fails.
[[noreturn]] void execProgram(const std::string& program, const std::vector<std::string>& arguments);
[[noreturn]] void execMotionlod(const std::vector<std::string>& arguments);

// An empty folder of its own for one test: <temp>/mlod_cli_<suite>_<pid>/<name>, removed
// when this process exits (test_files.h's processTempFolder).
std::filesystem::path freshFolder(const std::string& suite, const std::string& name);
// The names of the files in `dir`, sorted.
std::vector<std::string> filesIn(const std::filesystem::path& dir);

// The keys of a JSON object, in the document's (sorted) order.
inline std::vector<std::string> keysOf(const nlohmann::json& object) {
  std::vector<std::string> keys;
  for (const auto& item : object.items())
    keys.push_back(item.key());
  return keys;
}

} // namespace mlod::test
