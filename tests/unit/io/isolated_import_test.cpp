// The sandboxed import: same result as in-process, and a file that makes Assimp
// allocate without bound, hang or be cancelled comes back as an Error.

#include "io/asset_stream.h"
#include "io/importer.h"
#include "io/isolated_import.h"
#include "test_files.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <sys/stat.h>
#include <unistd.h>
#include <thread>
#include <vector>

namespace mlod {
namespace {

// Guards the pipe protocol: the isolated import gives the same asset, bit for bit.
TEST(IsolatedImport, SameAssetAsInProcess) {
  ImportOptions options;
  options.unitScale = 2.54 / 0.45;
  const Result<Asset> direct = importAsset(test::modelPath("BVH/01_01.bvh"), options);
  const Result<Asset> isolated = importAssetIsolated(test::modelPath("BVH/01_01.bvh"), options);
  ASSERT_TRUE(direct.ok() && isolated.ok()) << (isolated.ok() ? "" : isolated.message());
  std::string a, b;
  writeAssetStream(*direct, a);
  writeAssetStream(*isolated, b);
  EXPECT_EQ(a, b);
}

// Guards determinism (issue 29: one DAE gave 5 different `info --json` in 8 runs): each seed
// of the import fuzzer, the damaged inputs that import, and real files of several formats,
// imported in two worker processes (a fresh address space each, as the CLI imports), give
// the same asset bit for bit.
TEST(IsolatedImport, EachSeedImportsTheSameTwice) {
  std::vector<std::string> files;
  // a seed's first byte picks the format (import_fuzzer.cpp: bvh, obj, our asset stream)
  std::vector<std::filesystem::path> seeds;
  for (const std::filesystem::directory_entry& entry :
       std::filesystem::directory_iterator(MLOD_SOURCE_DIR "/tests/fuzz/corpus"))
    seeds.push_back(entry.path());
  std::sort(seeds.begin(), seeds.end());
  for (const std::filesystem::path& seed : seeds) {
    std::ifstream in(seed, std::ios::binary);
    std::ostringstream read;
    read << in.rdbuf();
    const std::string bytes = read.str();
    const char* formats[] = {"bvh", "obj", "stream"};
    const std::string format = bytes.empty() ? "stream" : formats[static_cast<unsigned char>(bytes[0]) % 3];
    if (format != "stream") // (our own format, not a file the importer opens)
      files.push_back(test::writeTemp("seed_" + seed.stem().string() + "." + format, bytes.substr(1)));
  }
  ASSERT_GE(files.size(), 3u);
  for (const char* bad : {"crash_segv_min.obj", "rotcube__038_g038.3ds"})
    files.push_back(std::string(MLOD_TEST_DATA_DIR "/bad/") + bad);
  for (const char* model : {"BVH/01_01.bvh", "X/BCN_Epileptic.X", "Collada/cube_tristrips.dae", "FBX/box.fbx",
                            "glTF2/BoxTextured-glTF-Binary/BoxTextured.glb", "3DS/CameraRollAnim.3ds"})
    files.push_back(test::modelPath(model));
  for (const std::string& file : files) {
    SCOPED_TRACE(file);
    const Result<Asset> first = importAssetIsolated(file);
    const Result<Asset> second = importAssetIsolated(file);
    ASSERT_TRUE(first.ok() && second.ok()) << (first.ok() ? second.message() : first.message());
    std::string a, b;
    writeAssetStream(*first, a);
    writeAssetStream(*second, b);
    EXPECT_EQ(a, b);
  }
}

// Guards error messages crossing the pipe.
TEST(IsolatedImport, ErrorsCrossThePipe) {
  const Result<Asset> asset = importAssetIsolated(test::writeTemp("empty.x", ""));
  ASSERT_FALSE(asset.ok());
  EXPECT_NE(asset.message().find("empty"), std::string::npos);
}

// Guards the memory limit on a file that makes Assimp allocate 16 GB
// (assimp-testmodels' invalid/OutOfMemory.off): the limit ends the worker, not the clock,
// in ASan builds too (where the limit is on the address space's growth).
TEST(IsolatedImport, RunawayImportIsStopped) {
  IsolationLimits limits;
  limits.timeoutSeconds = 60.0;
  limits.memoryBytes = std::size_t{2} << 30;
  const Result<Asset> asset = importAssetIsolated(test::modelPath("invalid/OutOfMemory.off"), {}, limits);
  ASSERT_FALSE(asset.ok());
  EXPECT_FALSE(asset.message().empty());
  EXPECT_EQ(asset.message().find("stopped after"), std::string::npos) << asset.message();
}

// Guards the timeout path alone: without a memory limit, OutOfMemory.off keeps Assimp
// busy for far longer than the one second allowed.
TEST(IsolatedImport, TimeoutStopsAHang) {
  IsolationLimits limits;
  limits.timeoutSeconds = 1.0;
  limits.memoryBytes = 0;
  const Result<Asset> asset = importAssetIsolated(test::modelPath("invalid/OutOfMemory.off"), {}, limits);
  ASSERT_FALSE(asset.ok());
  EXPECT_NE(asset.message().find("stopped after 1 s"), std::string::npos) << asset.message();
}

// Guards cancel from another thread.
TEST(IsolatedImport, CancelStopsTheWorker) {
  std::atomic<bool> cancel{false};
  IsolationLimits limits;
  limits.timeoutSeconds = 60.0;
  limits.memoryBytes = 0;
  limits.cancel = &cancel;
  std::thread canceller([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    cancel = true;
  });
  const auto start = std::chrono::steady_clock::now();
  const Result<Asset> asset = importAssetIsolated(test::modelPath("invalid/OutOfMemory.off"), {}, limits);
  canceller.join();
  ASSERT_FALSE(asset.ok());
  EXPECT_EQ(asset.message(), "import cancelled");
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(30));
}

// Guards the hang libFuzzer found in Assimp 5.2's SMD parser: the worker is stopped.
TEST(IsolatedImport, AssimpSmdHangIsStopped) {
  IsolationLimits limits;
  limits.timeoutSeconds = 2.0;
  const Result<Asset> asset = importAssetIsolated(test::dataPath("bad/assimp_smd_hang.smd"), {}, limits);
  ASSERT_FALSE(asset.ok());
  EXPECT_NE(asset.message().find("stopped after 2 s"), std::string::npos) << asset.message();
}

// Guards the crash path: inputs libFuzzer found that make Assimp 5.2 segfault. Under
// ASan the worker's own handler exits instead of dying by the signal.
TEST(IsolatedImport, AssimpCrashIsReported) {
  for (const char* file : {"bad/assimp_x_crash.x", "bad/assimp_md5mesh_crash.md5mesh"}) {
    SCOPED_TRACE(file);
    const Result<Asset> asset = importAssetIsolated(test::dataPath(file));
    ASSERT_FALSE(asset.ok());
    const std::string& message = asset.message();
    EXPECT_TRUE(message.find("crashed on this file (signal 11") != std::string::npos ||
                message.find("stopped without an answer") != std::string::npos)
        << message;
  }
}

// Guards special files: a FIFO is refused at once instead of blocking the reader.
TEST(IsolatedImport, FifoIsRefused) {
  const std::string fifo = test::writeTemp("walk.bvh", "") + ".fifo";
  ::unlink(fifo.c_str());
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const Result<Asset> asset = importAssetIsolated(fifo);
  ::unlink(fifo.c_str());
  ASSERT_FALSE(asset.ok());
  EXPECT_NE(asset.message().find("not a regular file"), std::string::npos) << asset.message();
}

// Guards the worker's lifetime: a parent killed with SIGKILL runs no handler, and its
// stuck worker ran at 100% CPU (or here, blocked) forever. It must die with its parent.
TEST(IsolatedImport, WorkerDiesWithItsParent) {
  const test::StuckImport stuck;
  const std::string& file = stuck.path();
  const pid_t parent = ::fork();
  ASSERT_GE(parent, 0);
  if (parent == 0) {
    IsolationLimits limits;
    limits.timeoutSeconds = 120.0;
    (void)importAssetIsolated(file, {}, limits);
    ::_exit(0);
  }
  const pid_t worker = test::workerOf(parent, 10.0);
  ::kill(parent, SIGKILL);
  ::waitpid(parent, nullptr, 0);
  ASSERT_GT(worker, 0) << "the import started no worker";
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (test::runs(worker) && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const bool orphanRuns = test::runs(worker);
  if (orphanRuns)
    ::kill(worker, SIGKILL); // leave nothing behind either way
  EXPECT_FALSE(orphanRuns) << "the worker outlived its parent";
}

// Guards the cancel flag: a stuck worker is stopped at once when the caller cancels.
TEST(IsolatedImport, CancelStopsAStuckWorker) {
  const test::StuckImport stuck;
  const std::string& file = stuck.path();
  std::atomic<bool> cancel{false};
  IsolationLimits limits;
  limits.timeoutSeconds = 120.0;
  limits.cancel = &cancel;
  std::thread canceller([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    cancel = true;
  });
  const Result<Asset> asset = importAssetIsolated(file, {}, limits);
  canceller.join();
  ASSERT_FALSE(asset.ok());
  EXPECT_EQ(asset.message(), "import cancelled");
}

// Guards the stream reader against truncated bytes (it must refuse, not read past the end).
TEST(AssetStream, RefusesTruncatedBytes) {
  const Result<Asset> asset = importAsset(test::modelPath("glTF2/simple_skin/simple_skin.gltf"));
  ASSERT_TRUE(asset.ok());
  std::string bytes;
  writeAssetStream(*asset, bytes);
  ASSERT_TRUE(readAssetStream(bytes).ok());
  for (std::size_t cut : {std::size_t{0}, std::size_t{7}, bytes.size() / 3, bytes.size() - 1})
    EXPECT_FALSE(readAssetStream(std::string_view(bytes).substr(0, cut)).ok()) << "cut at " << cut;
}

} // namespace
} // namespace mlod
