// Every file of Debian's assimp-testmodels (which deliberately holds broken files) either
// imports into a valid Asset or is refused with a message: no crash, no hang. One test
// per folder, through the sandboxed importer as the CLI and the studio use it.

#include "io/isolated_import.h"
#include "test_files.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

namespace mlod {
namespace {

std::vector<std::string> modelFolders() {
  std::vector<std::string> folders;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(MLOD_ASSIMP_MODELS, ec))
    if (entry.is_directory())
      folders.push_back(entry.path().filename().string());
  std::sort(folders.begin(), folders.end());
  return folders;
}

class Sweep : public ::testing::TestWithParam<std::string> {};

TEST_P(Sweep, EveryFileImportsOrIsRefusedClearly) {
  const std::filesystem::path folder = std::filesystem::path(MLOD_ASSIMP_MODELS) / GetParam();
  IsolationLimits limits;
  limits.timeoutSeconds = 30.0;
  limits.memoryBytes = std::size_t{4} << 30;
  int imported = 0, refused = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(folder)) {
    if (!entry.is_regular_file())
      continue;
    const std::string path = entry.path().string();
    const Result<Asset> asset = importAssetIsolated(path, {}, limits);
    if (asset.ok()) {
      EXPECT_FALSE(asset->validate()) << path;
      ++imported;
    } else {
      EXPECT_GT(asset.message().size(), 3u) << path;
      ++refused;
    }
  }
  std::printf("%s: %d imported, %d refused\n", GetParam().c_str(), imported, refused);
  EXPECT_GT(imported + refused, 0);
}

INSTANTIATE_TEST_SUITE_P(AssimpTestModels, Sweep, ::testing::ValuesIn(modelFolders()),
                         [](const ::testing::TestParamInfo<std::string>& param) {
                           std::string name = param.param;
                           std::replace_if(name.begin(), name.end(), [](char c) { return !std::isalnum(c); }, '_');
                           return name;
                         });

// Guards the sweep itself: the test models must be installed, or it proves nothing.
TEST(Sweep, TestModelsAreInstalled) { EXPECT_GE(modelFolders().size(), 40u); }

} // namespace
} // namespace mlod
