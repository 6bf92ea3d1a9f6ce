// `motionlod export` and `batch` on a terminal and off it, and what `motionlod info` reads
// back from the project's own glTF: the source's frame rate, frame count and clusters.
// The terminal is a pseudo-terminal (openpty) on stderr alone, stdout a pipe, each run bounded
// by a timeout.

#include "cli_runner.h"
#include "test_files.h"

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <poll.h>
#include <pty.h>
#include <sys/wait.h>
#include <unistd.h>

namespace mlod {
namespace {

namespace fs = std::filesystem;
using test::runMotionlod;

const std::string kSample = MLOD_SAMPLE;

fs::path freshFolder(const std::string& name) { return test::freshFolder("terminal", name); }

struct TerminalRun {
  int status = -1;
  std::string terminal; // what reached the terminal (stderr)
  std::string out;      // stdout (a pipe)
};

// Runs motionlod with stderr on a pseudo-terminal and stdout on a pipe; killed after `timeout`.
TerminalRun runOnTerminal(const std::vector<std::string>& arguments,
                          std::chrono::seconds timeout = std::chrono::seconds(60)) {
  TerminalRun run;
  int master = -1, slave = -1;
  winsize size{};
  size.ws_col = 200;
  size.ws_row = 40;
  int pipeFds[2];
  if (::openpty(&master, &slave, nullptr, nullptr, &size) != 0 || ::pipe(pipeFds) != 0) {
    ADD_FAILURE() << "no pseudo-terminal: " << std::strerror(errno);
    return run;
  }
  const pid_t child = ::fork();
  if (child == 0) {
    ::close(master);
    ::close(pipeFds[0]);
    ::dup2(pipeFds[1], STDOUT_FILENO);
    ::dup2(slave, STDERR_FILENO);
    const int null = ::open("/dev/null", O_RDONLY);
    ::dup2(null, STDIN_FILENO);
    test::execMotionlod(arguments);
  }
  ::close(slave);
  ::close(pipeFds[1]);
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  bool terminalOpen = true, pipeOpen = true;
  char buffer[4096];
  while ((terminalOpen || pipeOpen) && std::chrono::steady_clock::now() < deadline) {
    pollfd fds[2] = {{terminalOpen ? master : -1, POLLIN, 0}, {pipeOpen ? pipeFds[0] : -1, POLLIN, 0}};
    if (::poll(fds, 2, 100) <= 0)
      continue;
    if (fds[0].revents) {
      const ssize_t got = ::read(master, buffer, sizeof buffer);
      if (got > 0)
        run.terminal.append(buffer, std::size_t(got));
      else
        terminalOpen = false; // EIO once the child has closed its end
    }
    if (fds[1].revents) {
      const ssize_t got = ::read(pipeFds[0], buffer, sizeof buffer);
      if (got > 0)
        run.out.append(buffer, std::size_t(got));
      else
        pipeOpen = false;
    }
  }
  if (terminalOpen || pipeOpen) {
    ::kill(child, SIGKILL);
    ADD_FAILURE() << "motionlod did not finish within " << timeout.count() << " s";
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  ::close(master);
  ::close(pipeFds[0]);
  run.status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return run;
}

// On a terminal: one line rewritten in place ("\r", erase to its end), never a newline,
// naming each stage with its percent, cleared before the summary on stdout.
TEST(CliTerminal, ExportShowsOneUpdatingProgressLine) {
  const fs::path dir = freshFolder("export");
  const std::string out = (dir / "sample.glb").string();
  const TerminalRun run = runOnTerminal({"export", kSample, "--unit-scale", "cmu", "--plugin", "gltf", "-o", out});
  ASSERT_EQ(run.status, 0) << run.terminal;
  EXPECT_EQ(run.terminal.find('\n'), std::string::npos) << run.terminal;
  EXPECT_NE(run.terminal.find("\rimport"), std::string::npos) << run.terminal;
  EXPECT_NE(run.terminal.find("\rLOD package "), std::string::npos) << run.terminal;
  EXPECT_NE(run.terminal.find("\rexport "), std::string::npos) << run.terminal;
  EXPECT_NE(run.terminal.find("100%"), std::string::npos) << run.terminal;
  ASSERT_GE(run.terminal.size(), 4u);
  EXPECT_EQ(run.terminal.substr(run.terminal.size() - 4), "\r\033[K"); // cleared at the end
  EXPECT_NE(run.out.find("wrote " + out), std::string::npos) << run.out;
}

TEST(CliTerminal, QuietJsonAndPipesGetNoProgress) {
  const fs::path dir = freshFolder("quiet");
  const std::string out = (dir / "sample.glb").string();
  const std::vector<std::string> export_ = {"export", kSample, "--unit-scale", "cmu", "--plugin", "gltf", "-o", out};
  std::vector<std::string> quiet = export_;
  quiet.push_back("--quiet");
  const TerminalRun silenced = runOnTerminal(quiet);
  EXPECT_EQ(silenced.status, 0);
  EXPECT_EQ(silenced.terminal, "");
  std::vector<std::string> json = export_;
  json.push_back("--json");
  const TerminalRun document = runOnTerminal(json);
  EXPECT_EQ(document.status, 0);
  EXPECT_EQ(document.terminal, "");
  EXPECT_TRUE(nlohmann::json::parse(document.out)["ok"].get<bool>());
  const test::CliRun piped = runMotionlod(export_); // stderr is a file, not a terminal
  EXPECT_EQ(piped.status, 0);
  EXPECT_EQ(piped.err, "");
}

TEST(CliTerminal, BatchShowsJobsDoneAndTheStage) {
  const fs::path dir = freshFolder("batch");
  const nlohmann::json manifest = {
      {"jobs",
       {{{"input", kSample}, {"plugin", "gltf"}, {"output", (dir / "a.glb").string()}, {"unit_scale", "cmu"}},
        {{"input", kSample}, {"plugin", "gltf"}, {"output", (dir / "b.glb").string()}, {"unit_scale", "cmu"}}}}};
  const std::string path = (dir / "manifest.json").string();
  std::ofstream(path) << manifest.dump();
  const TerminalRun run = runOnTerminal({"batch", path});
  ASSERT_EQ(run.status, 0) << run.terminal;
  EXPECT_EQ(run.terminal.find('\n'), std::string::npos) << run.terminal;
  EXPECT_NE(run.terminal.find("batch 0/2 done; job 0 export "), std::string::npos) << run.terminal;
  EXPECT_NE(run.terminal.find("batch 1/2 done; job 1 export "), std::string::npos) << run.terminal;
  EXPECT_EQ(run.terminal.substr(run.terminal.size() - 4), "\r\033[K");
  const TerminalRun quiet = runOnTerminal({"batch", path, "--quiet"});
  EXPECT_EQ(quiet.status, 0);
  EXPECT_EQ(quiet.terminal, "");
}

// glTF stores no frame rate: the exporter writes the source's into the animations' extras
// and `info` reads it back (it came back at 30 fps, the resampling default, before), with
// the frame count and the clusters of MLOD_joint_clusters.
TEST(CliTerminal, InfoReadsTheSourceFpsFramesAndClustersOfItsGltf) {
  const fs::path dir = freshFolder("info");
  const nlohmann::json source = nlohmann::json::parse(runMotionlod({"info", kSample, "--json"}).out);
  for (const std::string name : {"sample.glb", "sample.gltf"}) {
    SCOPED_TRACE(name);
    const std::string out = (dir / name).string();
    ASSERT_EQ(runMotionlod({"export", kSample, "--unit-scale", "cmu", "--plugin", "gltf", "-o", out}).status, 0);
    const test::CliRun info = runMotionlod({"info", out, "--json"});
    ASSERT_EQ(info.status, 0) << info.err;
    const nlohmann::json doc = nlohmann::json::parse(info.out);
    ASSERT_EQ(doc["clips"].size(), 4u); // one per level
    for (std::size_t l = 0; l < 4; ++l) {
      const nlohmann::json& clip = doc["clips"][l];
      EXPECT_EQ(clip["fps"], source["clips"][0]["fps"]);
      EXPECT_EQ(clip["frames"], source["clips"][0]["frames"]);
      if (l == 0) {
        EXPECT_EQ(clip["clusters"], 0);
      } else {
        EXPECT_GT(clip["clusters"].get<int>(), 0) << clip.dump();
      }
    }
    const test::CliRun text = runMotionlod({"info", out});
    EXPECT_NE(text.out.find("120.000 fps"), std::string::npos) << text.out;
    EXPECT_NE(text.out.find(" clusters"), std::string::npos) << text.out;
  }
}

} // namespace
} // namespace mlod
