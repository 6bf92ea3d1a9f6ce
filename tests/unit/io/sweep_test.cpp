// Every file of Debian's assimp-testmodels (which deliberately holds broken files) either
// imports into a valid Asset or is refused with a message: no crash, no hang. One test
// per folder, through the sandboxed importer as the CLI and the studio use it. How many
// files of each folder import is pinned in tests/data/sweep_counts.json: a change to the
// importer that starts refusing (or accepting) files shows up here, not only a crash.

#include "io/isolated_import.h"
#include "test_files.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>

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

const nlohmann::json& expectedCounts() {
  static const nlohmann::json counts = [] {
    std::ifstream in(test::dataPath("sweep_counts.json"));
    return nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  }();
  return counts;
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
  const nlohmann::json& expected = expectedCounts()["folders"][GetParam()];
  ASSERT_TRUE(expected.is_object()) << GetParam() << " is not in tests/data/sweep_counts.json";
  EXPECT_EQ(imported, expected["imported"].get<int>()) << GetParam();
  EXPECT_EQ(refused, expected["refused"].get<int>()) << GetParam();
}

INSTANTIATE_TEST_SUITE_P(AssimpTestModels, Sweep, ::testing::ValuesIn(modelFolders()),
                         [](const ::testing::TestParamInfo<std::string>& param) {
                           std::string name = param.param;
                           std::replace_if(name.begin(), name.end(), [](char c) { return !std::isalnum(c); }, '_');
                           return name;
                         });

// Guards the sweep itself: the test models must be installed, or it proves nothing.
TEST(Sweep, TestModelsAreInstalled) { EXPECT_GE(modelFolders().size(), 40u); }

// Guards the committed table: it parses, names every installed folder and nothing else, and
// its totals are the sums of its rows (318 of 595 files import with assimp-testmodels 5.2.5).
TEST(Sweep, CommittedCountsCoverEveryFolder) {
  const nlohmann::json& counts = expectedCounts();
  ASSERT_TRUE(counts.is_object()) << "tests/data/sweep_counts.json does not parse";
  std::vector<std::string> listed;
  int imported = 0, refused = 0;
  for (const auto& [folder, row] : counts["folders"].items()) {
    listed.push_back(folder);
    imported += row["imported"].get<int>();
    refused += row["refused"].get<int>();
  }
  std::sort(listed.begin(), listed.end());
  EXPECT_EQ(listed, modelFolders());
  EXPECT_EQ(imported, counts["imported"].get<int>());
  EXPECT_EQ(refused, counts["refused"].get<int>());
}

} // namespace
} // namespace mlod
