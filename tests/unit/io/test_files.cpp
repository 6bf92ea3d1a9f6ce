#include "test_files.h"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

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

std::string modelPath(const std::string& relative) { return std::string(MLOD_ASSIMP_MODELS) + "/" + relative; }
std::string dataPath(const std::string& relative) { return std::string(MLOD_TEST_DATA_DIR) + "/" + relative; }

std::string writeTemp(const std::string& name, const std::string& content) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("mlod-test-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::filesystem::path file = dir / name;
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

} // namespace mlod::test
