#pragma once
// Paths to real test data and temporary files the tests write.

#include <filesystem>
#include <string>
#include <sys/types.h>

namespace mlod::test {

// <temp>/<stem><pid>, created; removed with everything in it when this process exits (a
// forked child leaves it to its parent). Every temporary file of the tests lives in one.
std::filesystem::path processTempFolder(const std::string& stem);

// A file of Debian's assimp-testmodels, e.g. modelPath("BVH/01_01.bvh").
std::string modelPath(const std::string& relative);
// A file of tests/data.
std::string dataPath(const std::string& relative);
// Writes `content` to a fresh file named `name` in this process's temporary folder
// (processTempFolder("mlod-test-")).
std::string writeTemp(const std::string& name, const std::string& content);
std::string readText(const std::string& path);

// A BVH file: one root "Hips" with `rootChannels` (e.g. "Xposition Yposition Zposition
// Zrotation Yrotation Xrotation"), a child "Chest" 10 units up with `chestChannels`, an
// End Site 5 units above it, and the motion rows given.
std::string makeBvh(const std::string& rootChannels, const std::string& chestChannels, int frames,
                    const std::string& frameTime, const std::string& rows);

// A child process of `parent` (an import worker), or 0 when none appears within `seconds`.
pid_t workerOf(pid_t parent, double seconds);
// Whether process `pid` still runs (a zombie waiting for its reaper does not).
bool runs(pid_t pid);
// An OBJ file the import worker of a test build (mlod_io_testing, motionlod_testing) blocks
// on, as a stuck import does: the worker never answers; only a timeout, a cancel or a kill
// ends it. The object sets kStuckImportVariable to the file for its lifetime; its
// destructor unsets it and removes the file. Release builds ignore the variable.
class StuckImport {
public:
  StuckImport();
  ~StuckImport();
  StuckImport(const StuckImport&) = delete;
  StuckImport& operator=(const StuckImport&) = delete;
  const std::string& path() const { return m_path; }

private:
  std::string m_path;
};

} // namespace mlod::test
