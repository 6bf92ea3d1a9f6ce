// The command-line contract of `motionlod batch MANIFEST.json [--shard I/N] [--jobs K]`:
// N shards together run every job exactly once and write the same bytes as one run of the
// whole manifest; a failing job does not stop the others and makes the exit status non-zero;
// a bad manifest or shard runs nothing.

#include "cli_runner.h"
#include "test_files.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <set>
#include <unistd.h>

namespace mlod {
namespace {

namespace fs = std::filesystem;
using test::keysOf;
using test::runMotionlod;

fs::path freshFolder(const std::string& name) {
  const fs::path dir = test::freshFolder("batch", name);
  fs::create_directories(dir / "out");
  return dir;
}

std::string bytesOf(const fs::path& file) {
  return test::readText(file.string());
}

// Seven jobs: the sample at several level sets and options, and the skinned character.
nlohmann::json library() {
  nlohmann::json jobs = nlohmann::json::array();
  const std::string sample = MLOD_SAMPLE;
  jobs.push_back({{"input", sample}, {"plugin", "bundle"}, {"output", "out/all.mlodb"}, {"unit_scale", "cmu"}});
  jobs.push_back({{"input", sample}, {"plugin", "bundle"}, {"output", "out/far.mlodb"}, {"levels", {3}}, {"unit_scale", "cmu"}});
  jobs.push_back({{"input", sample}, {"plugin", "bundle"}, {"output", "out/near.mlodb"}, {"levels", {0, 1}},
                  {"unit_scale", "cmu"}, {"options", {{"manifest", false}}}});
  jobs.push_back({{"input", test::modelPath("X/BCN_Epileptic.X")}, {"plugin", "bundle"}, {"output", "out/bcn.mlodb"},
                  {"unit_scale", 100}});
  jobs.push_back({{"input", sample}, {"plugin", "bundle"}, {"output", "out/motion.mlodb"}, {"unit_scale", 2.54 / 0.45},
                  {"options", {{"meshes", false}}}});
  jobs.push_back({{"input", sample}, {"plugin", "bundle"}, {"output", "out/two.mlodb"}, {"levels", {2, 3}},
                  {"unit_scale", "cmu"}});
  jobs.push_back({{"input", sample}, {"plugin", "bundle"}, {"output", "out/mid.mlodb"}, {"levels", {1, 2}},
                  {"unit_scale", "cmu"}});
  return {{"jobs", jobs}};
}

fs::path writeManifest(const fs::path& dir, const nlohmann::json& manifest) {
  const fs::path file = dir / "manifest.json";
  std::ofstream(file) << manifest.dump(2);
  return file;
}

TEST(CliBatch, ShardsCoverEveryJobOnceWithTheSameBytes) {
  const nlohmann::json manifest = library();
  const std::size_t jobs = manifest["jobs"].size();
  const fs::path whole = freshFolder("whole");
  const test::CliRun one = runMotionlod({"batch", writeManifest(whole, manifest).string(), "--json"});
  ASSERT_EQ(one.status, 0) << one.err;
  const nlohmann::json report = nlohmann::json::parse(one.out);
  EXPECT_EQ(keysOf(report), (std::vector<std::string>{"failed", "jobs", "manifest", "seconds", "shard", "succeeded"}));
  EXPECT_EQ(report["succeeded"], int(jobs));
  EXPECT_EQ(report["failed"], 0);
  ASSERT_EQ(report["jobs"].size(), jobs);
  EXPECT_EQ(keysOf(report["jobs"][0]), (std::vector<std::string>{"bytes", "exit", "index", "input", "message", "ok",
                                                                 "output", "plugin", "seconds"}));

  const int shards = 3;
  const fs::path split = freshFolder("split");
  const fs::path splitManifest = writeManifest(split, manifest);
  std::multiset<int> seen;
  for (int i = 0; i < shards; ++i) {
    const test::CliRun run = runMotionlod(
        {"batch", splitManifest.string(), "--shard", std::to_string(i) + "/" + std::to_string(shards), "--jobs", "2",
         "--json"});
    ASSERT_EQ(run.status, 0) << run.err;
    const nlohmann::json part = nlohmann::json::parse(run.out);
    EXPECT_EQ(part["shard"]["index"], i);
    EXPECT_EQ(part["shard"]["count"], shards);
    for (const nlohmann::json& job : part["jobs"]) {
      EXPECT_EQ(job["index"].get<int>() % shards, i);
      EXPECT_TRUE(job["ok"].get<bool>()) << job.dump();
      seen.insert(job["index"].get<int>());
    }
  }
  std::multiset<int> expected;
  for (std::size_t i = 0; i < jobs; ++i)
    expected.insert(int(i));
  EXPECT_EQ(seen, expected); // every job exactly once

  // the same bytes whatever the shard and the parallelism, manifests included
  std::set<std::string> wholeFiles, splitFiles;
  for (const fs::directory_entry& entry : fs::directory_iterator(whole / "out"))
    wholeFiles.insert(entry.path().filename().string());
  for (const fs::directory_entry& entry : fs::directory_iterator(split / "out"))
    splitFiles.insert(entry.path().filename().string());
  EXPECT_EQ(wholeFiles, splitFiles);
  EXPECT_EQ(wholeFiles.size(), jobs + 6); // all but one job write a .json manifest beside their bundle
  for (const std::string& name : wholeFiles)
    EXPECT_TRUE(bytesOf(whole / "out" / name) == bytesOf(split / "out" / name)) << name;
}

TEST(CliBatch, AFailingJobDoesNotStopTheOthers) {
  nlohmann::json manifest = library();
  manifest["jobs"] = nlohmann::json::array({manifest["jobs"][1],
                                            {{"input", "missing.bvh"}, {"plugin", "bundle"}, {"output", "out/m.mlodb"}},
                                            {{"input", MLOD_SAMPLE}, {"plugin", "nosuch"}, {"output", "out/n.mlodb"}},
                                            manifest["jobs"][2]});
  const fs::path dir = freshFolder("failing");
  const test::CliRun run = runMotionlod({"batch", writeManifest(dir, manifest).string()});
  EXPECT_EQ(run.status, 2) << run.err; // the first failed job's status: bad input
  EXPECT_NE(run.err.find("error: " + (dir / "missing.bvh").string() + ": "), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("no exporter plugin 'nosuch'"), std::string::npos) << run.err;
  EXPECT_NE(run.out.find("2 succeeded, 2 failed"), std::string::npos) << run.out;
  EXPECT_TRUE(fs::exists(dir / "out" / "far.mlodb"));
  EXPECT_TRUE(fs::exists(dir / "out" / "near.mlodb"));
  EXPECT_FALSE(fs::exists(dir / "out" / "m.mlodb"));
  EXPECT_FALSE(fs::exists(dir / "out" / "n.mlodb"));
}

// An output whose suffix is not its plugin's is a manifest error, as `export` refuses it:
// exit 2 naming the job, checked over the whole manifest before any job runs (every shard).
TEST(CliBatch, AnOutputOfAnotherFormatRunsNothing) {
  const fs::path dir = freshFolder("suffix");
  nlohmann::json manifest = library();
  manifest["jobs"].push_back(
      {{"input", MLOD_SAMPLE}, {"plugin", "gltf"}, {"output", "out/walk.mlodb"}, {"unit_scale", "cmu"}});
  const fs::path file = writeManifest(dir, manifest);
  for (const std::string shard : {"0/1", "0/2", "1/2"}) {
    const test::CliRun run = runMotionlod({"batch", file.string(), "--shard", shard, "--json"});
    EXPECT_EQ(run.status, 2) << shard;
    EXPECT_EQ(run.err, "error: " + file.string() + ": job 7: " + (dir / "out" / "walk.mlodb").string() +
                           ": the gltf exporter writes .glb or .gltf files, not .mlodb\n");
    EXPECT_TRUE(run.out.empty()) << run.out;
  }
  EXPECT_TRUE(fs::is_empty(dir / "out"));
}

TEST(CliBatch, BadManifestsAndShardsRunNothing) {
  const fs::path dir = freshFolder("bad");
  const struct {
    std::string text;
    std::string reason;
  } manifests[] = {
      {"not json", "not JSON"},
      {"{\"work\": []}", "not a batch manifest"},
      {"{\"jobs\": [{\"input\": \"a.bvh\", \"plugin\": \"bundle\"}]}", "job 0: \"output\" must be a non-empty string"},
      {"{\"jobs\": [{\"input\": \"a\", \"plugin\": \"bundle\", \"output\": \"b\", \"extra\": 1}]}",
       "unknown key \"extra\""},
      {"{\"jobs\": [{\"input\": \"a\", \"plugin\": \"bundle\", \"output\": \"b\", \"options\": {\"x\": [1]}}]}",
       "must be a bool, number or string"},
      {"{\"jobs\": [{\"input\": \"a\", \"plugin\": \"bundle\", \"output\": \"b\", \"skinning\": \"both\"}]}",
       "job 0: \"skinning\" must be \"gpu\" or \"cpu\""},
      {"{\"jobs\": [{\"input\": \"a\", \"plugin\": \"bundle\", \"output\": \"b\", \"skinning\": 1}]}",
       "job 0: \"skinning\" must be \"gpu\" or \"cpu\""},
  };
  for (const auto& m : manifests) {
    const fs::path file = dir / "m.json";
    std::ofstream(file) << m.text;
    const test::CliRun run = runMotionlod({"batch", file.string()});
    EXPECT_EQ(run.status, 2) << m.text;
    EXPECT_EQ(run.err.rfind("error: " + file.string() + ": ", 0), 0u) << run.err;
    EXPECT_NE(run.err.find(m.reason), std::string::npos) << run.err;
  }
  const fs::path file = writeManifest(dir, library());
  for (const std::string shard : {"3/3", "1", "-1/2", "0/0", "a/b"}) {
    const test::CliRun run = runMotionlod({"batch", file.string(), "--shard", shard});
    EXPECT_EQ(run.status, 2) << shard;
    EXPECT_NE(run.err.find("--shard '" + shard + "' is not I/N"), std::string::npos) << run.err;
  }
  EXPECT_TRUE(fs::is_empty(dir / "out"));
}

} // namespace
} // namespace mlod
