#include "test_files.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sys/stat.h>
#include <thread>
#include <fstream>
#include <mutex>
#include <sstream>
#include <unistd.h>
#include <utility>
#include <vector>

namespace mlod::test {

namespace {
int channelCount(const std::string& channels) {
  std::istringstream in(channels);
  int count = 0;
  for (std::string word; in >> word;)
    ++count;
  return count;
}
} // namespace

namespace {
// The folders processTempFolder() made, each with the process that made it.
struct TempFolders {
  std::mutex mutex;
  std::vector<std::pair<pid_t, std::filesystem::path>> folders;
  ~TempFolders() {
    for (const auto& [owner, folder] : folders) {
      std::error_code ignored;
      if (owner == ::getpid())
        std::filesystem::remove_all(folder, ignored);
    }
  }
};
TempFolders& tempFolders() {
  static TempFolders folders;
  return folders;
}
} // namespace

std::filesystem::path processTempFolder(const std::string& stem) {
  const std::filesystem::path folder = std::filesystem::temp_directory_path() / (stem + std::to_string(::getpid()));
  std::filesystem::create_directories(folder);
  TempFolders& made = tempFolders();
  const std::lock_guard lock(made.mutex);
  const std::pair<pid_t, std::filesystem::path> entry{::getpid(), folder};
  if (std::find(made.folders.begin(), made.folders.end(), entry) == made.folders.end())
    made.folders.push_back(entry);
  return folder;
}

std::string modelPath(const std::string& relative) { return std::string(MLOD_ASSIMP_MODELS) + "/" + relative; }
std::string dataPath(const std::string& relative) { return std::string(MLOD_TEST_DATA_DIR) + "/" + relative; }

std::string writeTemp(const std::string& name, const std::string& content) {
  const std::filesystem::path file = processTempFolder("mlod-test-") / name;
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out << content;
  return file.string();
}

std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string makeBvh(const std::string& rootChannels, const std::string& chestChannels, int frames,
                    const std::string& frameTime, const std::string& rows) {
  std::ostringstream out;
  out << "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 0\n  CHANNELS " << channelCount(rootChannels) << " " << rootChannels
      << "\n  JOINT Chest\n  {\n    OFFSET 0 10 0\n    CHANNELS " << channelCount(chestChannels) << " "
      << chestChannels << "\n    End Site\n    {\n      OFFSET 0 5 0\n    }\n  }\n}\nMOTION\nFrames: " << frames
      << "\nFrame Time: " << frameTime << "\n"
      << rows;
  return out.str();
}

// A child of `parent` (its import worker), or 0 when it has none within `seconds`.
pid_t workerOf(pid_t parent, double seconds) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < deadline) {
    for (const auto& entry : std::filesystem::directory_iterator("/proc")) {
      const std::string name = entry.path().filename().string();
      if (name.find_first_not_of("0123456789") != std::string::npos)
        continue;
      std::ifstream stat(entry.path() / "stat");
      std::string line;
      std::getline(stat, line);
      const std::size_t close = line.rfind(')');
      if (close == std::string::npos)
        continue;
      char state = 0;
      int ppid = 0;
      if (std::sscanf(line.c_str() + close + 1, " %c %d", &state, &ppid) == 2 && ppid == parent)
        return static_cast<pid_t>(std::stoi(name));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return 0;
}

// Whether `pid` still runs (a zombie waiting for a reaper runs no more).
bool runs(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  if (!std::getline(stat, line))
    return false;
  const std::size_t close = line.rfind(')');
  return close != std::string::npos && close + 2 < line.size() && line[close + 2] != 'Z' && line[close + 2] != 'X';
}

// An OBJ that the import worker blocks on (kStuckImportVariable names it), as a stuck
// import does: a FIFO material library no longer blocks (the import refuses it).
StuckImport::StuckImport() : m_path((processTempFolder("mlod-stuck-") / "s.obj").string()) {
  std::ofstream(m_path) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  ::setenv("MLOD_TEST_STUCK_IMPORT", m_path.c_str(), 1); // io/isolated_import.h's kStuckImportVariable
}

StuckImport::~StuckImport() {
  ::unsetenv("MLOD_TEST_STUCK_IMPORT");
  std::error_code ignored;
  std::filesystem::remove(m_path, ignored);
}

} // namespace mlod::test
