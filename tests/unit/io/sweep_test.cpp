// Every file of Debian's assimp-testmodels (which deliberately holds broken files) either
// imports into a valid Asset or is refused with a message: no crash, no hang. One test
// per folder, through the sandboxed importer as the CLI and the studio use it. How many
// files of each folder import is pinned in tests/data/sweep_counts.json: a change to the
// importer that starts refusing (or accepting) files shows up here, not only a crash. A
// file the worker did not finish within the limit is neither: it is a timeout, tried once
// more with a longer limit (a loaded machine), and a hang if that one runs out too.

#include "io/isolated_import.h"
#include "test_files.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

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

const nlohmann::json& sweepCounts() {
  static const nlohmann::json counts = [] {
    std::ifstream in(test::dataPath("sweep_counts.json"));
    return nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  }();
  return counts;
}

class Sweep : public ::testing::TestWithParam<std::string> {};

enum class Outcome { Imported, Refused, TimedOut };

// One file through the sandboxed importer: imported (a valid Asset), refused (with a
// message) or timed out (the worker stopped at the limit: no answer either way).
Outcome sweepOne(const std::string& path, double timeoutSeconds) {
  IsolationLimits limits;
  limits.timeoutSeconds = timeoutSeconds;
  limits.memoryBytes = std::size_t{4} << 30;
  const auto start = std::chrono::steady_clock::now();
  const Result<Asset> asset = importAssetIsolated(path, {}, limits);
  if (asset.ok()) {
    EXPECT_FALSE(asset->validate()) << path;
    return Outcome::Imported;
  }
  if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >= timeoutSeconds)
    return Outcome::TimedOut;
  EXPECT_GT(asset.message().size(), 3u) << path;
  return Outcome::Refused;
}

TEST_P(Sweep, EveryFileImportsOrIsRefusedClearly) {
  const std::filesystem::path folder = std::filesystem::path(MLOD_ASSIMP_MODELS) / GetParam();
  constexpr double kTimeoutSeconds = 30.0;      // none of these files takes 6 s on an idle machine
  constexpr double kRetryTimeoutSeconds = 120.0; // a timeout's second try
  int imported = 0, refused = 0;
  std::vector<std::string> hung;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(folder)) {
    if (!entry.is_regular_file())
      continue;
    const std::string path = entry.path().string();
    Outcome outcome = sweepOne(path, kTimeoutSeconds);
    if (outcome == Outcome::TimedOut) {
      std::printf("%s: no answer within %.0f s, tried again with %.0f s\n", path.c_str(), kTimeoutSeconds,
                  kRetryTimeoutSeconds);
      outcome = sweepOne(path, kRetryTimeoutSeconds);
    }
    imported += outcome == Outcome::Imported;
    refused += outcome == Outcome::Refused;
    if (outcome == Outcome::TimedOut)
      hung.push_back(path);
  }
  std::printf("%s: %d imported, %d refused, %zu timed out\n", GetParam().c_str(), imported, refused, hung.size());
  for (const std::string& path : hung)
    ADD_FAILURE() << path << ": timed out twice (" << kTimeoutSeconds << " s, " << kRetryTimeoutSeconds
                  << " s): the import hangs";
  if (!hung.empty())
    return; // the counts of a folder with an unanswered file say nothing more
  EXPECT_GT(imported + refused, 0);
  const nlohmann::json& expected = sweepCounts()["folders"][GetParam()];
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
  const nlohmann::json& counts = sweepCounts();
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
