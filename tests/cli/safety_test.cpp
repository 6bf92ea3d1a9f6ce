// Nothing lost, nothing hangs (docs/architecture.md sections 6 and 9; issue 16): an output is
// never an input (by file identity) nor an existing device or FIFO; every input is a regular
// file of bounded size, so a FIFO or a link to /dev/zero is refused at once; a batch
// manifest is checked whole before any job runs; an output name that is not valid UTF-8 is
// written under the exact bytes given. Runs that could hang are bounded by a timeout.

#include "cli_runner.h"
#include "test_files.h"

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <optional>
#include <sys/stat.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace mlod {
namespace {

namespace fs = std::filesystem;
using test::filesIn;
using test::runMotionlod;

constexpr int kTimeout = 20; // seconds; every run here takes well under one

fs::path freshFolder(const std::string& name) { return test::freshFolder("safety", name); }


std::string bytesOf(const fs::path& file) {
  return test::readText(file.string());
}

// A copy of the sample BVH (a CMU excerpt) in `dir`.
fs::path sampleIn(const fs::path& dir, const std::string& name = "walk.bvh") {
  fs::copy_file(MLOD_SAMPLE, dir / name);
  return dir / name;
}

bool startsWith(const std::string& text, const std::string& prefix) {
  return text.rfind(prefix, 0) == 0;
}

// `export a.bvh -o a.bvh` (and through a hard link or a symlink) would overwrite its input.
TEST(CliSafety, ExportNeverWritesItsInput) {
  const fs::path dir = freshFolder("own_input");
  const fs::path input = sampleIn(dir);
  const std::string before = bytesOf(input);
  fs::create_hard_link(input, dir / "hard.glb");
  fs::create_symlink(input, dir / "link.glb");
  for (const fs::path& output : {input, dir / "hard.glb", dir / "link.glb", dir / "." / "walk.bvh"}) {
    const test::CliRun run = runMotionlod(
        {"export", input.string(), "--unit-scale", "cmu", "--plugin", "gltf", "-o", output.string()}, kTimeout);
    EXPECT_EQ(run.status, 2) << output;
    EXPECT_TRUE(startsWith(run.err, "error: " + output.string() + ": ")) << run.err;
    EXPECT_NE(run.err.find("it would be overwritten"), std::string::npos) << run.err;
    EXPECT_EQ(run.err.find("import"), std::string::npos) << "refused before any work: " << run.err;
  }
  EXPECT_EQ(bytesOf(input), before);
  EXPECT_EQ(filesIn(dir), (std::vector<std::string>{"hard.glb", "link.glb", "walk.bvh"}));
  // glTF with split_levels writes OUT_LOD<n>.glb: those are outputs too
  fs::create_hard_link(input, dir / "split_LOD1.glb");
  const test::CliRun split = runMotionlod({"export", input.string(), "--unit-scale", "cmu", "--plugin", "gltf",
                                           "--option", "split_levels=true", "-o", (dir / "split.glb").string()},
                                          kTimeout);
  EXPECT_EQ(split.status, 2) << split.err;
  EXPECT_TRUE(startsWith(split.err, "error: " + (dir / "split_LOD1.glb").string() + ": the output is the same file"))
      << split.err;
  EXPECT_EQ(bytesOf(input), before);
}

// `export p.mlod --plugin report -o p.mlod`, and a project's asset as the output.
TEST(CliSafety, ExportNeverWritesItsProjectOrItsAssets) {
  const fs::path dir = freshFolder("project");
  const fs::path asset = sampleIn(dir);
  const nlohmann::json project = {
      {"format", "motionlod-project"},
      {"version", 1},
      {"alpha", 5.0},
      {"mode", "greedy"},
      {"levels", {{{"threshold", 5.0}}}},
      {"assets", {{{"path", "walk.bvh"}, {"unit_scale", 5.6444}, {"joints", nlohmann::json::object()}}}}};
  const fs::path file = dir / "p.mlod";
  std::ofstream(file) << project.dump();
  const std::string before = bytesOf(file), assetBefore = bytesOf(asset);
  for (const fs::path& output : {file, asset}) {
    const test::CliRun run =
        runMotionlod({"export", file.string(), "--plugin", "report", "-o", output.string()}, kTimeout);
    EXPECT_EQ(run.status, 2) << output;
    EXPECT_NE(run.err.find("it would be overwritten"), std::string::npos) << run.err;
  }
  EXPECT_EQ(bytesOf(file), before);
  EXPECT_EQ(bytesOf(asset), assetBefore);
}

// An existing output that is no regular file is never replaced (as root, -o /dev/null
// would otherwise replace /dev/null with a regular file).
TEST(CliSafety, ExportRefusesAnOutputThatIsNoRegularFile) {
  const fs::path dir = freshFolder("special_output");
  const fs::path input = sampleIn(dir);
  const fs::path fifo = dir / "out.mlodb";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const fs::path manifestFifo = dir / "m.mlodb";
  ASSERT_EQ(::mkfifo((manifestFifo.string() + ".json").c_str(), 0600), 0); // the bundle's manifest
  for (const fs::path& output : {fifo, manifestFifo, fs::path("/dev/null")}) {
    const test::CliRun run = runMotionlod(
        {"export", input.string(), "--unit-scale", "cmu", "--plugin", "bundle", "-o", output.string()}, kTimeout);
    EXPECT_EQ(run.status, 2) << output;
    EXPECT_NE(run.err.find("not a regular file"), std::string::npos) << run.err;
  }
  EXPECT_TRUE(fs::is_fifo(fifo));
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  EXPECT_EQ(filesIn(dir), (std::vector<std::string>{"m.mlodb.json", "out.mlodb", "walk.bvh"}));
}

// A FIFO named .mlod, .mlodb or a manifest blocked the reader forever; a link to /dev/zero
// read until memory ran out. Both are refused at once, whatever the command.
TEST(CliSafety, InputsThatAreNoRegularFilesAreRefusedAtOnce) {
  const fs::path dir = freshFolder("special_input");
  std::vector<fs::path> fifos, zeros;
  for (const char* name : {"a.mlod", "a.mlodb", "a.json", "a.bvh"}) {
    fifos.push_back(dir / (std::string("fifo_") + name));
    ASSERT_EQ(::mkfifo(fifos.back().c_str(), 0600), 0);
    zeros.push_back(dir / (std::string("zero_") + name));
    fs::create_symlink("/dev/zero", zeros.back());
  }
  const auto commandFor = [&](const fs::path& file) -> std::vector<std::string> {
    const std::string ext = file.extension().string();
    if (ext == ".json")
      return {"batch", file.string()};
    if (ext == ".mlodb")
      return {"info", file.string()};
    return {"export", file.string(), "--plugin", "bundle", "-o", (dir / "out.mlodb").string()};
  };
  for (const std::vector<fs::path>* kind : {&fifos, &zeros})
    for (const fs::path& file : *kind) {
      const test::CliRun run = runMotionlod(commandFor(file), kTimeout);
      EXPECT_EQ(run.status, 2) << file << ": " << run.err;
      EXPECT_TRUE(startsWith(run.err, "error: " + file.string() + ": it is a ")) << run.err;
      EXPECT_NE(run.err.find("not a regular file"), std::string::npos) << run.err;
    }
  const test::CliRun info = runMotionlod({"info", fifos[0].string()}, kTimeout);
  EXPECT_EQ(info.status, 2) << info.err;
  const test::CliRun simplify = runMotionlod({"simplify", zeros[3].string(), "--threshold", "5"}, kTimeout);
  EXPECT_EQ(simplify.status, 2) << simplify.err;
  EXPECT_NE(simplify.err.find("it is a device, not a regular file"), std::string::npos) << simplify.err;
  EXPECT_FALSE(fs::exists(dir / "out.mlodb"));
}

// An OBJ whose mtllib named a FIFO blocked until the import timeout (or Ctrl+C): a file
// an asset reads beside it is refused like the asset itself, at once.
TEST(CliSafety, SideFilesThatAreNoRegularFilesAreRefusedAtOnce) {
  const fs::path dir = freshFolder("side_files");
  ASSERT_EQ(::mkfifo((dir / "fifo.mtl").c_str(), 0600), 0);
  fs::create_symlink("/dev/zero", dir / "zero.mtl");
  for (const char* library : {"fifo.mtl", "zero.mtl"}) {
    const fs::path obj = dir / (std::string(library) + ".obj");
    std::ofstream(obj) << "mtllib " << library << "\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n";
    const test::CliRun run = runMotionlod({"info", obj.string()}, kTimeout);
    EXPECT_EQ(run.status, 2) << obj << ": " << run.err;
    EXPECT_TRUE(startsWith(run.err, "error: " + obj.string() + ": the file it reads beside it, '")) << run.err;
    EXPECT_NE(run.err.find(std::string(library) + "', is refused: it is a "), std::string::npos) << run.err;
    EXPECT_NE(run.err.find("not a regular file"), std::string::npos) << run.err;
  }
  // A regular mtllib still imports.
  std::ofstream(dir / "ok.mtl") << "newmtl a\nKd 1 0 0\n";
  std::ofstream(dir / "ok.obj") << "mtllib ok.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n";
  const test::CliRun ok = runMotionlod({"info", (dir / "ok.obj").string()}, kTimeout);
  EXPECT_EQ(ok.status, 0) << ok.err;
}

// A project of 70,000 levels ran for minutes growing memory: levels are capped on load.
TEST(CliSafety, ProjectLevelsAreCappedOnLoad) {
  const fs::path dir = freshFolder("levels");
  sampleIn(dir);
  nlohmann::json levels = nlohmann::json::array();
  for (int i = 0; i < 70000; ++i)
    levels.push_back({{"threshold", 5.0 + i}});
  const nlohmann::json project = {
      {"format", "motionlod-project"},
      {"version", 1},
      {"alpha", 5.0},
      {"mode", "greedy"},
      {"levels", levels},
      {"assets", {{{"path", "walk.bvh"}, {"unit_scale", 1.0}, {"joints", nlohmann::json::object()}}}}};
  const fs::path file = dir / "many.mlod";
  std::ofstream(file) << project.dump();
  const test::CliRun run =
      runMotionlod({"export", file.string(), "--plugin", "bundle", "-o", (dir / "o.mlodb").string()}, kTimeout);
  EXPECT_EQ(run.status, 2) << run.err;
  EXPECT_NE(run.err.find("70001 LOD levels; a project may have at most 32"), std::string::npos) << run.err;
  const test::CliRun negative = [&] {
    nlohmann::json bad = project;
    bad["levels"] = {{{"threshold", 5.0}}};
    bad["assets"][0]["unit_scale"] = -2.0;
    std::ofstream(file) << bad.dump();
    return runMotionlod({"info", file.string()}, kTimeout);
  }();
  EXPECT_EQ(negative.status, 2);
  EXPECT_TRUE(startsWith(negative.err, "error: " + file.string() + ": asset 0: unit_scale -2")) << negative.err;
  // unit_scale 0 was accepted: a written unit must be positive; the file's own unit is no key.
  const test::CliRun zero = [&] {
    nlohmann::json bad = {
        {"format", "motionlod-project"},
        {"version", 3},
        {"alpha", 5.0},
        {"mode", "greedy"},
        {"lods",
         {{"projection", {{"vertical_fov_degrees", 60.0}, {"viewport_height_pixels", 1080.0}}},
          {"bounding_radius_cm", 0.0},
          {"levels", nlohmann::json::array()}}},
        {"assets", {{{"path", "walk.bvh"}, {"unit_scale", 0}, {"joints", nlohmann::json::object()}}}}};
    std::ofstream(file) << bad.dump();
    return runMotionlod({"simplify", file.string(), "--threshold", "5"}, kTimeout);
  }();
  EXPECT_EQ(zero.status, 2);
  EXPECT_TRUE(startsWith(zero.err, "error: " + file.string() + ": asset 0: unit_scale must be positive")) << zero.err;
}

// A Latin-1 output name was written as U+FFFD yet reported success: the file now has the
// exact bytes given (the bundle's manifest too), and nothing else stays in the folder.
TEST(CliSafety, OutputNamesAreKeptAsBytes) {
  const fs::path dir = freshFolder("latin1");
  const fs::path input = sampleIn(dir);
  const std::string latin1 = "caf\xe9";
  for (const char* plugin : {"bundle", "gltf"}) {
    const std::string name = latin1 + (std::string(plugin) == "bundle" ? ".mlodb" : ".glb");
    const test::CliRun run = runMotionlod(
        {"export", input.string(), "--unit-scale", "cmu", "--plugin", plugin, "-o", (dir / name).string()}, kTimeout);
    EXPECT_EQ(run.status, 0) << run.err;
    EXPECT_NE(run.out.find("wrote " + (dir / name).string()), std::string::npos) << run.out;
    EXPECT_GT(fs::file_size(dir / name), 1000u);
  }
  EXPECT_EQ(filesIn(dir),
            (std::vector<std::string>{latin1 + ".glb", latin1 + ".mlodb", latin1 + ".mlodb.json", "walk.bvh"}));
  const test::CliRun info = runMotionlod({"info", (dir / (latin1 + ".mlodb")).string()}, kTimeout);
  EXPECT_EQ(info.status, 0) << info.err;
}

// --- the import worker: stopped with its parent ------------------------------------

// `motionlod ARGS` started in the background, stderr to `err`; its PID. The test build
// (motionlod_testing): its import worker blocks on a test::StuckImport.
pid_t startMotionlod(const std::vector<std::string>& arguments, const fs::path& err) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    std::FILE* out = std::freopen(err.c_str(), "w", stderr);
    (void)out;
    test::execProgram(MLOD_MOTIONLOD_TESTING, arguments);
  }
  return pid;
}

// waitpid() for at most `seconds`; the raw status, or -1 (and the process killed) on timeout.
int waitAtMost(pid_t pid, double seconds) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  int status = 0;
  while (::waitpid(pid, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() > deadline) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      return -1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return status;
}

// Whether `file` holds `text` within `seconds` (a child's stderr, written as it goes).
bool saysWithin(const fs::path& file, const std::string& text, double seconds) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (bytesOf(file).find(text) == std::string::npos) {
    if (std::chrono::steady_clock::now() > deadline)
      return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return true;
}

bool goneWithin(pid_t pid, double seconds) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (test::runs(pid) && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const bool gone = !test::runs(pid);
  if (!gone)
    ::kill(pid, SIGKILL); // leave nothing behind either way
  return gone;
}

// Ctrl+C during `info` stops a stuck import at once (not after --import-timeout): the
// worker is stopped and motionlod ends by SIGINT, as a shell expects.
TEST(CliSafety, CtrlCStopsAStuckImportAtOnce) {
  const fs::path dir = freshFolder("ctrl_c");
  const test::StuckImport stuck;
  const pid_t cli = startMotionlod({"info", stuck.path(), "--import-timeout", "600"}, dir / "err");
  const pid_t worker = test::workerOf(cli, 10.0);
  ASSERT_GT(worker, 0);
  // the worker exists from fork() on; Ctrl+C comes once it is blocked in the hook (sent
  // earlier, it could stop the worker before the hook said so: the CI failure of stop 36)
  EXPECT_TRUE(saysWithin(dir / "err", "MLOD_TEST_STUCK_IMPORT names " + stuck.path(), 10.0))
      << "the hook did not fire, or fired without saying so: " << bytesOf(dir / "err");
  ::kill(cli, SIGINT);
  const int status = waitAtMost(cli, 10.0);
  ASSERT_NE(status, -1) << "motionlod did not stop on SIGINT";
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGINT) << status;
  EXPECT_NE(bytesOf(dir / "err").find("interrupted: the import was stopped"), std::string::npos)
      << bytesOf(dir / "err");
  EXPECT_TRUE(goneWithin(worker, 10.0)) << "the worker outlived the interrupted command";
}

// kill -9 of motionlod while it imports left the worker running forever.
TEST(CliSafety, KilledCommandTakesItsWorkerAlong) {
  const fs::path dir = freshFolder("kill9");
  const test::StuckImport stuck;
  const pid_t cli = startMotionlod({"info", stuck.path(), "--import-timeout", "600"}, dir / "err");
  const pid_t worker = test::workerOf(cli, 10.0);
  ASSERT_GT(worker, 0);
  ::kill(cli, SIGKILL);
  waitAtMost(cli, 10.0);
  EXPECT_TRUE(goneWithin(worker, 10.0)) << "the worker outlived motionlod";
}

// The stuck-import hook is in test builds only: the released motionlod imports the file
// that MLOD_TEST_STUCK_IMPORT names like any other.
TEST(CliSafety, ReleaseBuildHasNoStuckImportHook) {
  const test::StuckImport stuck;
  const test::CliRun run = runMotionlod({"info", stuck.path(), "--import-timeout", "10"}, kTimeout);
  EXPECT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(run.err.find("test hook"), std::string::npos) << run.err;
}

// --- the bundle and its manifest: whole after any failure ----------------------------

// Runs `script` with sh; its exit status and output (stdout and stderr together).
std::pair<int, std::string> shell(const std::string& script) {
  const std::string out = test::writeTemp("shell.out", "");
  const int raw = std::system(("timeout -k 2 60 sh -c '" + script + "' > '" + out + "' 2>&1").c_str());
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw), test::readText(out)};
}

// A full disk said "Unknown error" for glTF and the bundle: it is named, with the file, and
// nothing stays on the disk. A small tmpfs in a mount namespace of its own fills up.
TEST(CliSafety, FullDiskIsNamedWithTheFile) {
  if (shell("unshare -m true").first != 0)
    GTEST_SKIP() << "no mount namespace here (unshare -m): the write-failure test below covers the path";
  const fs::path dir = freshFolder("full_disk");
  const std::string input = sampleIn(dir).string();
  for (const char* name : {"out.mlodb", "out.glb"}) {
    const std::string plugin = std::string(name) == "out.mlodb" ? "bundle" : "gltf";
    const std::string disk = (dir / "disk").string();
    fs::create_directories(disk);
    const auto [status, output] = shell("unshare -m sh -c \"mount -t tmpfs -o size=64k none " + disk + " && " +
                                        MLOD_MOTIONLOD + " export " + input + " --unit-scale cmu --plugin " + plugin +
                                        " -o " + disk + "/" + name + "; echo exit=\\$?; ls -A " + disk + "\"");
    EXPECT_NE(output.find("error: " + disk + "/" + name + ": cannot write: No space left on device"), std::string::npos)
        << output;
    EXPECT_TRUE(output.size() >= 7 && output.compare(output.size() - 7, 7, "exit=1\n") == 0)
        << "exit 1 and nothing left on the disk: " << output;
  }
}

// Any write failure (here the file size limit: "File too large") leaves the previous
// bundle and manifest exactly as they were, and no temporary.
TEST(CliSafety, FailedExportKeepsThePreviousPair) {
  const fs::path dir = freshFolder("keep_pair");
  const std::string input = sampleIn(dir).string();
  const fs::path bundle = dir / "x.mlodb";
  const test::CliRun first = runMotionlod(
      {"export", input, "--unit-scale", "cmu", "--plugin", "bundle", "--levels", "0,1", "-o", bundle.string()},
      kTimeout);
  ASSERT_EQ(first.status, 0) << first.err;
  const std::string bundleBefore = bytesOf(bundle), manifestBefore = bytesOf(bundle.string() + ".json");
  const auto [status, output] = shell(std::string("trap \"\" XFSZ; exec prlimit --fsize=100000 ") + MLOD_MOTIONLOD +
                                      " export " + input + " --unit-scale cmu --plugin bundle -o " + bundle.string());
  EXPECT_EQ(status, 1) << output;
  EXPECT_NE(output.find("error: " + bundle.string() + ": cannot write: File too large"), std::string::npos) << output;
  EXPECT_EQ(bytesOf(bundle), bundleBefore);
  EXPECT_EQ(bytesOf(bundle.string() + ".json"), manifestBefore);
  EXPECT_EQ(filesIn(dir), (std::vector<std::string>{"walk.bvh", "x.mlodb", "x.mlodb.json"}));
}

// With glTF's split_levels an export writes a file per level. When the last cannot take
// its place (here an immutable file: even root's rename is refused), every level already
// placed gets its previous version back byte for byte, and no temporary stays (issue 29:
// the old LOD0 and LOD1 were gone when LOD2's rename failed).
// motionlod's environment for one scope: LD_PRELOAD of the no-exchange shim
// (tests/cli/support/no_exchange.cpp), its refusals counted in `log`.
class NoExchange {
public:
  explicit NoExchange(const fs::path& log) {
    ::setenv("LD_PRELOAD", MLOD_NO_EXCHANGE, 1);
    ::setenv("MLOD_NO_EXCHANGE_LOG", log.c_str(), 1);
  }
  ~NoExchange() {
    ::unsetenv("LD_PRELOAD");
    ::unsetenv("MLOD_NO_EXCHANGE_LOG");
  }
  NoExchange(const NoExchange&) = delete;
  NoExchange& operator=(const NoExchange&) = delete;
};

int linesOf(const fs::path& file) {
  std::ifstream in(file);
  int lines = 0;
  for (std::string line; std::getline(in, line);)
    ++lines;
  return lines;
}

// A glTF export with split levels whose highest level file cannot be replaced (immutable):
// the export fails and every old level stays byte-identical, no temporary left. `exchange`:
// the file system exchanges names (ext4, tmpfs), else the writer renames aside.
void splitLevelsWhoseLastFileCannotLand(const std::string& folder, bool exchange) {
  const fs::path dir = freshFolder(folder);
  const fs::path log = freshFolder(folder + "_log") / "refused.txt";
  const std::string input = sampleIn(dir).string();
  const auto exportAt = [&](const char* unit) {
    const std::optional<NoExchange> shim = exchange ? std::nullopt : std::make_optional<NoExchange>(log);
    return runMotionlod({"export", input, "--unit-scale", unit, "--plugin", "gltf", "--option", "split_levels=true",
                         "-o", (dir / "split.glb").string()},
                        kTimeout);
  };
  const test::CliRun first = exportAt("cmu");
  ASSERT_EQ(first.status, 0) << first.err;
  const std::vector<std::string> names = filesIn(dir);
  ASSERT_GE(names.size(), 3u) << "two levels at least, and the input";
  std::vector<std::string> before;
  for (const std::string& name : names)
    before.push_back(bytesOf(dir / name));
  const fs::path last = dir / names[names.size() - 2]; // the highest level ("walk.bvh" sorts last)
  if (shell("chattr +i " + last.string()).first != 0)
    GTEST_SKIP() << "no immutable files here (chattr +i): AtomicWrite.SetWhoseLastFileCannotLandKeepsEveryOldFile "
                    "covers the rollback with a folder in the way";
  const int refusedBefore = linesOf(log);
  const test::CliRun second = exportAt("m"); // other sizes: every level's bytes differ
  shell("chattr -i " + last.string());
  EXPECT_EQ(second.status, 1) << second.err;
  EXPECT_TRUE(startsWith(second.err, "error: ")) << second.err;
  EXPECT_NE(second.err.find(last.string() + ": cannot write: Operation not permitted"), std::string::npos) << second.err;
  for (std::size_t i = 0; i < names.size(); ++i)
    EXPECT_EQ(bytesOf(dir / names[i]), before[i]) << names[i];
  EXPECT_EQ(filesIn(dir), names) << "no temporary left";
  if (!exchange) { // the levels before the last were replaced by rename-aside, then put back
    EXPECT_GE(linesOf(log) - refusedBefore, static_cast<int>(names.size()) - 1) << "exchanges refused by the shim";
  }
}

TEST(CliSafety, SplitLevelsWhoseLastFileCannotLandKeepEveryOldLevel) {
  splitLevelsWhoseLastFileCannotLand("split_last_fails", true);
}

// The same where the file system cannot exchange two names (a preloaded shim refuses
// RENAME_EXCHANGE with EINVAL): the writer renames the old files aside (the immutable last
// one cannot be: it is copied aside) and puts every one back.
TEST(CliSafety, SplitLevelsWhoseLastFileCannotLandKeepEveryOldLevelWithoutExchange) {
  splitLevelsWhoseLastFileCannotLand("split_last_fails_no_exchange", false);
}

// Without RENAME_EXCHANGE an export still replaces its outputs: a bundle and its manifest
// exported twice hold the second export's bytes, nothing beside them (no version kept
// aside, no temporary), and the shim saw the exchanges it refused.
TEST(CliSafety, ExportWithoutExchangeReplacesItsOutputs) {
  const fs::path dir = freshFolder("no_exchange_replace");
  const fs::path log = freshFolder("no_exchange_replace_log") / "refused.txt";
  const std::string input = sampleIn(dir).string();
  const fs::path bundle = dir / "walk.mlodb";
  const auto exportAt = [&](const char* unit) {
    const NoExchange shim(log);
    return runMotionlod({"export", input, "--unit-scale", unit, "--plugin", "bundle", "-o", bundle.string()},
                        kTimeout);
  };
  const test::CliRun first = exportAt("cmu");
  ASSERT_EQ(first.status, 0) << first.err;
  EXPECT_EQ(linesOf(log), 0) << "nothing to replace the first time";
  const std::string firstBytes = bytesOf(bundle);
  const test::CliRun second = exportAt("m");
  ASSERT_EQ(second.status, 0) << second.err;
  EXPECT_EQ(linesOf(log), 2) << "the bundle and its manifest, each refused once";
  EXPECT_NE(bytesOf(bundle), firstBytes) << "the second export's bundle";
  const test::CliRun info = runMotionlod({"info", bundle.string(), "--json"}, kTimeout);
  EXPECT_EQ(info.status, 0) << info.err;
  EXPECT_EQ(filesIn(dir), (std::vector<std::string>{"walk.bvh", "walk.mlodb", "walk.mlodb.json"}));
}

// The repro files of issue 29 (../shared/repro, kept in tests/data/bad), through the commands
// that crashed or hung on them: each answers within the timeout, with a result or with exit 2
// and an error naming the file, never a signal, and a refused export writes nothing.
TEST(CliSafety, ReproFilesOfQaRoundThreeEndCleanly) {
  const fs::path dir = freshFolder("repro");
  const std::string bad = std::string(MLOD_TEST_DATA_DIR) + "/bad/";
  const struct {
    std::string file;
    std::vector<std::string> command; // the file and -o OUT are added
    int status;
    const char* reason; // in the error, where refused
  } cases[] = {
      // every OFFSET 1e38: "height: inf cm", and export spun in the pixel budget
      {bad + "hang_offset_1e38_2frames.bvh", {"info"}, 2, "non-finite position"},
      {bad + "hang_offset_1e38_2frames.bvh", {"export", "--plugin", "bundle"}, 2, "non-finite position"},
      {bad + "hang_offset_1e38_2frames.bvh", {"simplify", "--threshold", "5,50"}, 2, "non-finite position"},
      // spider.obj with face lines deleted: SIGSEGV in the mesh simplifier
      {bad + "crash_segv_min.obj", {"meshlod", "--ratio", "0.5"}, 0, ""},
      {bad + "crash_segv_min.obj", {"export", "--plugin", "gltf"}, 0, ""},
      // one bit flipped: 786,645 frames, past 1,200 s in the key search
      {bad + "rotcube__038_g038.3ds", {"export", "--plugin", "bundle"}, 2, "more than joint posture clustering takes"},
      // scripts/qa-campaign.py: triangle.smd cut after 30 bytes loops in Assimp's SMD parser;
      // the worker is stopped (by default after kDefaultImportTimeoutSeconds, within the
      // minute; here sooner)
      {bad + "smd_truncated_hang.smd", {"info", "--import-timeout", "2"}, 2, "import stopped after 2 s"},
      {bad + "smd_truncated_hang.smd", {"export", "--import-timeout", "2", "--plugin", "bundle"}, 2,
       "import stopped after 2 s"},
  };
  for (const auto& c : cases) {
    std::vector<std::string> arguments{c.command.front(), c.file};
    arguments.insert(arguments.end(), c.command.begin() + 1, c.command.end());
    const bool exports = c.command.front() == "export";
    const fs::path output = dir / (c.command.back() == "bundle" ? "out.mlodb" : "out.glb");
    if (exports) {
      arguments.push_back("-o");
      arguments.push_back(output.string());
    }
    SCOPED_TRACE(c.file + " " + c.command.front());
    const test::CliRun run = runMotionlod(arguments, kTimeout);
    EXPECT_EQ(run.status, c.status) << run.err;
    if (c.status == 2) {
      EXPECT_TRUE(startsWith(run.err, "error: " + c.file + ": ")) << run.err;
      EXPECT_NE(run.err.find(c.reason), std::string::npos) << run.err;
      EXPECT_TRUE(filesIn(dir).empty()) << "a refused export writes nothing";
    } else if (exports) {
      EXPECT_TRUE(fs::is_regular_file(output));
      fs::remove(output);
    }
  }
}

// A kill between the bundle's rename and its manifest's leaves a new bundle beside the old
// manifest: the manifest carries the bundle's size and CRC-32, and `info` says it does not
// belong. The killed writer's temporaries go on the next export.
TEST(CliSafety, InfoTellsAManifestOfAnotherBundle) {
  const fs::path dir = freshFolder("mismatch");
  const std::string input = sampleIn(dir).string();
  for (const char* levels : {"0,1", "2,3"}) {
    const test::CliRun run =
        runMotionlod({"export", input, "--unit-scale", "cmu", "--plugin", "bundle", "--levels", levels, "-o",
                      (dir / (std::string(levels) == "0,1" ? "a.mlodb" : "b.mlodb")).string()},
                     kTimeout);
    ASSERT_EQ(run.status, 0) << run.err;
  }
  const test::CliRun whole = runMotionlod({"info", (dir / "a.mlodb").string()}, kTimeout);
  EXPECT_EQ(whole.status, 0) << whole.err;
  EXPECT_EQ(whole.err, "");
  fs::copy_file(dir / "b.mlodb", dir / "a.mlodb", fs::copy_options::overwrite_existing);
  const test::CliRun torn = runMotionlod({"info", (dir / "a.mlodb").string()}, kTimeout);
  EXPECT_EQ(torn.status, 0) << torn.err;
  EXPECT_TRUE(startsWith(torn.err, "warning: " + (dir / "a.mlodb.json").string() + ": it does not belong to " +
                                       (dir / "a.mlodb").string()))
      << torn.err;

  const pid_t dead = ::fork();
  if (dead == 0)
    ::_exit(0);
  ::waitpid(dead, nullptr, 0);
  const std::string leftover = ".a.mlodb.mlod-tmp-" + std::to_string(dead) + "-XyZ123";
  std::ofstream(dir / leftover) << "half a bundle";
  const test::CliRun again = runMotionlod(
      {"export", input, "--unit-scale", "cmu", "--plugin", "bundle", "-o", (dir / "a.mlodb").string()}, kTimeout);
  EXPECT_EQ(again.status, 0) << again.err;
  EXPECT_FALSE(fs::exists(dir / leftover));
}

// --- clear errors instead of raw exceptions ------------------------------------------

// Latin-1 bytes in joint and file names made --json, glTF and report exports exit 1 with a
// raw "[json.exception.type_error.316]". Names are made valid on import (and said so);
// file names stay bytes, written with U+FFFD in JSON, with a warning.
TEST(CliSafety, Latin1NamesNeverThrow) {
  const fs::path dir = freshFolder("latin1_names");
  std::string bvh =
      test::makeBvh("Xposition Yposition Zposition Zrotation Yrotation Xrotation", "Zrotation Yrotation Xrotation", 3,
                    "0.04", "0 0 0 0 0 0 0 0 0\n0 1 0 10 0 0 20 0 0\n0 2 0 20 0 0 40 0 0\n");
  bvh.replace(bvh.find("Chest"), 5, "Cou\xE9");
  const fs::path file = dir / "d\xE9mo.bvh";
  std::ofstream(file) << bvh;
  const test::CliRun info = runMotionlod({"info", file.string(), "--json"}, kTimeout);
  EXPECT_EQ(info.status, 0) << info.err;
  EXPECT_EQ(info.err.find("json.exception"), std::string::npos) << info.err;
  EXPECT_NE(info.err.find("not valid UTF-8"), std::string::npos) << info.err;
  const nlohmann::json doc = nlohmann::json::parse(info.out, nullptr, false);
  ASSERT_FALSE(doc.is_discarded()) << info.out;
  EXPECT_NE(info.out.find("Cou\xEF\xBF\xBD"), std::string::npos) << info.out;
  const test::CliRun bench = runMotionlod({"bench-crowd", file.string(), "--characters", "2", "--frames", "2",
                                           "--threshold", "50", "--repetitions", "1", "--json"},
                                          kTimeout);
  EXPECT_EQ(bench.status, 0) << bench.err;
  EXPECT_EQ(bench.err.find("json.exception"), std::string::npos) << bench.err;
  EXPECT_FALSE(nlohmann::json::parse(bench.out, nullptr, false).is_discarded()) << bench.out;
  EXPECT_NE(bench.out.find("d\xEF\xBF\xBDmo.bvh"), std::string::npos) << bench.out;
  for (const char* plugin : {"gltf", "report"}) {
    const fs::path out = dir / (std::string("out.") + (std::string(plugin) == "gltf" ? "gltf" : "json"));
    const test::CliRun run =
        runMotionlod({"export", file.string(), "--plugin", plugin, "-o", out.string(), "--json"}, kTimeout);
    EXPECT_EQ(run.status, 0) << plugin << ": " << run.err;
    EXPECT_EQ(run.err.find("json.exception"), std::string::npos) << run.err;
    EXPECT_FALSE(nlohmann::json::parse(run.out, nullptr, false).is_discarded()) << run.out;
    EXPECT_FALSE(nlohmann::json::parse(bytesOf(out), nullptr, false).is_discarded()) << plugin;
  }
}

// A BVH whose offsets are all zero failed export with "pixel figures must be finite": the
// character has no size, which the message now says.
TEST(CliSafety, CharacterWithoutSizeIsNamedAsSuch) {
  const fs::path dir = freshFolder("no_size");
  std::string bvh =
      test::makeBvh("Xposition Yposition Zposition Zrotation Yrotation Xrotation", "Zrotation Yrotation Xrotation", 2,
                    "0.04", "0 0 0 0 0 0 0 0 0\n0 0 0 10 0 0 20 0 0\n");
  for (const char* offset : {"OFFSET 0 10 0", "OFFSET 0 5 0"})
    bvh.replace(bvh.find(offset), std::string(offset).size(), "OFFSET 0 0 0");
  const fs::path file = dir / "flat.bvh";
  std::ofstream(file) << bvh;
  const test::CliRun run =
      runMotionlod({"export", file.string(), "--plugin", "bundle", "-o", (dir / "o.mlodb").string()}, kTimeout);
  EXPECT_EQ(run.status, 2) << run.err;
  EXPECT_TRUE(startsWith(run.err, "error: " + file.string() + ": LOD: the character has no size")) << run.err;
  EXPECT_FALSE(fs::exists(dir / "o.mlodb"));
}

// BVH "Frame Time: inf" became 25 fps without a word.
TEST(CliSafety, BvhFrameTimeInfIsRefused) {
  const fs::path dir = freshFolder("frame_time");
  const fs::path file = dir / "inf.bvh";
  std::ofstream(file) << test::makeBvh("Xposition Yposition Zposition Zrotation Yrotation Xrotation",
                                       "Zrotation Yrotation Xrotation", 1, "inf", "0 0 0 0 0 0 0 0 0\n");
  const test::CliRun run = runMotionlod({"info", file.string()}, kTimeout);
  EXPECT_EQ(run.status, 2);
  EXPECT_TRUE(startsWith(run.err, "error: " + file.string() + ": its Frame Time 'inf' is not a finite number"))
      << run.err;
}

// --- batch: the whole manifest is checked before any job runs -------------------------

fs::path writeManifest(const fs::path& dir, const std::vector<nlohmann::json>& jobs) {
  const fs::path file = dir / "manifest.json";
  nlohmann::json doc = nlohmann::json::object();
  doc["jobs"] = jobs;
  std::ofstream(file) << doc.dump(2);
  return file;
}

nlohmann::json bundleJob(const std::string& input, const std::string& output) {
  return {{"input", input}, {"plugin", "bundle"}, {"output", output}, {"unit_scale", "cmu"}};
}

TEST(CliSafety, BatchRefusesOutputsThatWouldLoseData) {
  const fs::path dir = freshFolder("batch");
  sampleIn(dir, "a.bvh");
  sampleIn(dir, "b.bvh");
  fs::create_directories(dir / "out");
  const std::string aBefore = bytesOf(dir / "a.bvh");
  const struct {
    std::vector<nlohmann::json> jobs;
    std::string reason;
  } cases[] = {
      {{bundleJob("a.bvh", "out/ok.mlodb"), bundleJob("b.bvh", "b.bvh")},
       "job 1: " + (dir / "b.bvh").string() + ": the output is the same file as the input " + (dir / "b.bvh").string()},
      {{bundleJob("a.bvh", "out/ok.mlodb"), bundleJob("b.bvh", "a.bvh")},
       "the same file as the input " + (dir / "a.bvh").string()},
      {{bundleJob("a.bvh", "manifest.json")}, "the same file as the input"},
      {{bundleJob("a.bvh", "out/x.mlodb"), bundleJob("b.bvh", "out/../out/x.mlodb")},
       "job 1: " + (dir / "out/x.mlodb").string() + ": job 0 writes the same file"},
      {{bundleJob("a.bvh", "out/x"), {{"input", "b.bvh"}, {"plugin", "gltf"}, {"output", "out/x.json"}}},
       "job 0 writes the same file"},
      {{bundleJob("a.bvh", "/dev/null")}, "not a regular file"},
  };
  for (const auto& c : cases) {
    const fs::path manifest = writeManifest(dir, c.jobs);
    const std::string manifestBefore = bytesOf(manifest);
    const test::CliRun run = runMotionlod({"batch", manifest.string(), "--allow-outside"}, kTimeout);
    EXPECT_EQ(run.status, 2) << c.reason;
    EXPECT_TRUE(startsWith(run.err, "error: " + manifest.string() + ": ")) << run.err;
    EXPECT_NE(run.err.find(c.reason), std::string::npos) << run.err;
    EXPECT_TRUE(fs::is_empty(dir / "out")) << "no job may run: " << c.reason;
    EXPECT_EQ(bytesOf(manifest), manifestBefore);
  }
  EXPECT_EQ(bytesOf(dir / "a.bvh"), aBefore);
}

// A missing output folder is no bad manifest: exit 1, which a farm retries; a bad unit
// scale in the manifest is (exit 2, nothing runs).
TEST(CliSafety, BatchMissingFolderIsExitOneManifestErrorIsTwo) {
  const fs::path dir = freshFolder("batch_folder");
  sampleIn(dir, "a.bvh");
  const fs::path manifest = writeManifest(dir, {bundleJob("a.bvh", "missing/x.mlodb")});
  const test::CliRun run = runMotionlod({"batch", manifest.string()}, kTimeout);
  EXPECT_EQ(run.status, 1) << run.err;
  EXPECT_NE(run.err.find("the folder " + (dir / "missing").string() + " does not exist"), std::string::npos) << run.err;
  nlohmann::json zero = bundleJob("a.bvh", "x.mlodb");
  zero["unit_scale"] = 0;
  const test::CliRun bad = runMotionlod({"batch", writeManifest(dir, {zero}).string()}, kTimeout);
  EXPECT_EQ(bad.status, 2) << bad.err;
  EXPECT_NE(bad.err.find("job 0: \"unit_scale\" must be a positive number"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(dir / "x.mlodb"));
}

// Outputs outside the manifest's folder are written with a warning; --allow-outside
// silences it.
TEST(CliSafety, BatchWarnsAboutOutputsOutsideItsFolder) {
  const fs::path dir = freshFolder("batch_outside");
  fs::create_directories(dir / "jobs");
  sampleIn(dir / "jobs", "a.bvh");
  const fs::path manifest = writeManifest(dir / "jobs", {bundleJob("a.bvh", "../elsewhere.mlodb")});
  const test::CliRun warned = runMotionlod({"batch", manifest.string()}, kTimeout);
  EXPECT_EQ(warned.status, 0) << warned.err;
  EXPECT_NE(warned.err.find("warning: " + manifest.string() + ": job 0 writes " + (dir / "elsewhere.mlodb").string() +
                            ", outside the manifest's folder"),
            std::string::npos)
      << warned.err;
  EXPECT_TRUE(fs::exists(dir / "elsewhere.mlodb"));
  const test::CliRun allowed = runMotionlod({"batch", manifest.string(), "--allow-outside"}, kTimeout);
  EXPECT_EQ(allowed.status, 0) << allowed.err;
  EXPECT_EQ(allowed.err.find("warning"), std::string::npos) << allowed.err;
}

} // namespace
} // namespace mlod
