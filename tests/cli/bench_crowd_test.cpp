// The command-line contract of docs/architecture.md section 6 and issue 4 for `bench-crowd`: the JSON
// keys, figures that hold whatever the machine's speed (no timed assertion), skinning
// figures where the file has a mesh, and `error: FILE: reason` with exit 2 for bad input.

#include "cli_runner.h"
#include "test_files.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace mlod {
namespace {

using test::runMotionlod;

// Guards the JSON document of the issue: file, characters, frames, threshold, threads,
// simplified_joint_percent, full and lod {seconds, joints_evaluated, char_frames_per_second},
// speedup = full seconds / LOD seconds, memory; and that the LOD samples fewer joints.
TEST(CliBenchCrowd, JsonOnCmuClip) {
  const test::CliRun run =
      runMotionlod({"bench-crowd", test::modelPath("BVH/01_01.bvh"), "--characters", "20", "--frames", "10",
                    "--threshold", "50", "--unit-scale", "cmu", "--repetitions", "1", "--json"});
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json doc = nlohmann::json::parse(run.out);
  for (const char* key : {"file", "characters", "frames", "threshold", "threads", "simplified_joint_percent", "full",
                          "lod", "speedup", "memory"})
    EXPECT_TRUE(doc.contains(key)) << key;
  EXPECT_EQ(doc["characters"], 20);
  EXPECT_EQ(doc["frames"], 10);
  EXPECT_EQ(doc["threshold"], 50.0);
  EXPECT_EQ(doc["threads"], 1);
  EXPECT_GT(doc["simplified_joint_percent"].get<double>(), 50.0);
  for (const char* side : {"full", "lod"}) {
    const nlohmann::json& figures = doc[side];
    ASSERT_TRUE(figures.is_object()) << side;
    EXPECT_GT(figures["seconds"].get<double>(), 0.0) << side;
    EXPECT_GT(figures["char_frames_per_second"].get<double>(), 0.0) << side;
    EXPECT_GT(figures["joints_evaluated"].get<std::int64_t>(), 0) << side;
  }
  // full detail samples every animated joint, every character-frame
  EXPECT_EQ(doc["full"]["joints_evaluated"].get<std::int64_t>(), 20 * 10 * doc["animated_joints"].get<std::int64_t>());
  EXPECT_LT(doc["lod"]["joints_evaluated"].get<std::int64_t>(), doc["full"]["joints_evaluated"].get<std::int64_t>());
  EXPECT_NEAR(doc["speedup"].get<double>(),
              doc["full"]["seconds"].get<double>() / doc["lod"]["seconds"].get<double>(), 1e-9);
  EXPECT_GT(doc["memory"]["full_bytes"].get<std::int64_t>(), 0);
  EXPECT_GT(doc["memory"]["lod_bytes"].get<std::int64_t>(), 0);
  EXPECT_GT(doc["memory"]["per_character_bytes"].get<std::int64_t>(), 0);
  EXPECT_FALSE(doc.contains("skinning")) << "a BVH file has no mesh";
}

// Guards the skinning figures where the file has a skinned mesh, and threads.
TEST(CliBenchCrowd, SkinningFiguresOnCharacter) {
  const test::CliRun run = runMotionlod({"bench-crowd", test::modelPath("X/BCN_Epileptic.X"), "--characters", "8",
                                         "--frames", "4", "--threshold", "50", "--threads", "2", "--repetitions", "1",
                                         "--json"});
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json doc = nlohmann::json::parse(run.out);
  EXPECT_EQ(doc["threads"], 2);
  ASSERT_TRUE(doc.contains("skinning"));
  EXPECT_EQ(doc["skinning"]["vertices"], 3014);
  EXPECT_GT(doc["skinning"]["full_seconds"].get<double>(), 0.0);
  EXPECT_GT(doc["skinning"]["lod_seconds"].get<double>(), 0.0);
}

// Guards the error contract: exit 2 and `error: FILE: reason`, nothing on stdout.
TEST(CliBenchCrowd, BadInputExitsTwo) {
  const test::CliRun missing =
      runMotionlod({"bench-crowd", "/nonexistent/file.bvh", "--threshold", "50", "--characters", "2", "--frames", "2"});
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.err.find("error: /nonexistent/file.bvh: "), std::string::npos) << missing.err;
  EXPECT_TRUE(missing.out.empty());
  const test::CliRun negative = runMotionlod(
      {"bench-crowd", test::modelPath("BVH/01_01.bvh"), "--threshold", "-1", "--characters", "2", "--frames", "2"});
  EXPECT_EQ(negative.status, 2);
  EXPECT_NE(negative.err.find("error: "), std::string::npos) << negative.err;
  const test::CliRun noMotion =
      runMotionlod({"bench-crowd", test::modelPath("OBJ/spider.obj"), "--threshold", "50", "--characters", "2"});
  EXPECT_EQ(noMotion.status, 2);
  EXPECT_NE(noMotion.err.find("no animation clip"), std::string::npos) << noMotion.err;
  const test::CliRun zero = runMotionlod(
      {"bench-crowd", test::modelPath("BVH/01_01.bvh"), "--threshold", "50", "--characters", "0"});
  EXPECT_EQ(zero.status, 2);
}

} // namespace
} // namespace mlod
