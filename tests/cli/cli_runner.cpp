#include "cli_runner.h"

#include "test_files.h"

#include <algorithm>
#include <cstdlib>
#include <sys/wait.h>
#include <unistd.h>

namespace mlod::test {

void execProgram(const std::string& program, const std::vector<std::string>& arguments) {
  std::vector<char*> argv{const_cast<char*>(program.c_str())};
  for (const std::string& argument : arguments)
    argv.push_back(const_cast<char*>(argument.c_str()));
  argv.push_back(nullptr);
  ::execv(program.c_str(), argv.data());
  ::_exit(127);
}

void execMotionlod(const std::vector<std::string>& arguments) { execProgram(MLOD_MOTIONLOD, arguments); }

namespace {
std::string quote(const std::string& text) {
  std::string out = "'";
  for (char c : text)
    out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}
} // namespace

CliRun runMotionlod(const std::vector<std::string>& arguments) { return runMotionlod(arguments, 0); }

CliRun runMotionlod(const std::vector<std::string>& arguments, int timeoutSeconds) {
  const std::string out = writeTemp("cli.out", "");
  const std::string err = writeTemp("cli.err", "");
  std::string command = timeoutSeconds > 0 ? "timeout -k 2 " + std::to_string(timeoutSeconds) + " " : std::string();
  command += quote(MLOD_MOTIONLOD);
  for (const std::string& argument : arguments)
    command += " " + quote(argument);
  command += " > " + quote(out) + " 2> " + quote(err);
  const int raw = std::system(command.c_str());
  CliRun run;
  run.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
  run.out = readText(out);
  run.err = readText(err);
  return run;
}

std::filesystem::path freshFolder(const std::string& suite, const std::string& name) {
  namespace fs = std::filesystem;
  const fs::path dir = processTempFolder("mlod_cli_" + suite + "_") / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::vector<std::string> filesIn(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  for (const std::filesystem::directory_entry& entry : std::filesystem::directory_iterator(dir))
    names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

} // namespace mlod::test
