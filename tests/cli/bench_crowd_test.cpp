// The command-line contract of docs/architecture.md section 6 and issue 4 for `bench-crowd`: the JSON
// keys, figures that hold whatever the machine's speed (no timed assertion), skinning
// figures where the file has a mesh, and `error: FILE: reason` with exit 2 for bad input.

#include "../unit/real_files.h"
#include "cli_runner.h"
#include "test_files.h"

#include <algorithm>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

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
  EXPECT_NEAR(doc["speedup"].get<double>(), doc["full"]["seconds"].get<double>() / doc["lod"]["seconds"].get<double>(),
              1e-9);
  // one ratio per repetition: its full run's seconds over its LOD run's
  ASSERT_EQ(doc["speedup_pairs"].size(), 1u);
  EXPECT_NEAR(doc["speedup_pairs"][0].get<double>(),
              doc["full"]["repetition_seconds"][0].get<double>() / doc["lod"]["repetition_seconds"][0].get<double>(),
              1e-9);
  EXPECT_GT(doc["memory"]["full_bytes"].get<std::int64_t>(), 0);
  EXPECT_GT(doc["memory"]["lod_bytes"].get<std::int64_t>(), 0);
  EXPECT_GT(doc["memory"]["per_character_bytes"].get<std::int64_t>(), 0);
  EXPECT_FALSE(doc.contains("skinning")) << "a BVH file has no mesh";
}

// Guards the skinning figures where the file has a skinned mesh, and threads.
TEST(CliBenchCrowd, SkinningFiguresOnCharacter) {
  const test::CliRun run =
      runMotionlod({"bench-crowd", test::modelPath("X/BCN_Epileptic.X"), "--characters", "8", "--frames", "4",
                    "--threshold", "50", "--threads", "2", "--repetitions", "1", "--json"});
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
  const test::CliRun zero =
      runMotionlod({"bench-crowd", test::modelPath("BVH/01_01.bvh"), "--threshold", "50", "--characters", "0"});
  EXPECT_EQ(zero.status, 2);
}

// Guards the --scene contract (docs/architecture.md section 6, the paper's Figure 12): the
// JSON keys; four configurations with the same agents and frames, none at level 0 (every
// agent skins the original mesh), skeletal with level 0's mesh, mesh and both with the
// levels' meshes; speedup.x = none.frame_ms / x.frame_ms; each level's figures. On every
// animated fixture character, level 0's vertices and joints checked against `info --json`
// of the same file (its skinned meshes and skeleton).
class SceneJson : public ::testing::TestWithParam<std::string> {};

TEST_P(SceneJson, OnCharacter) {
  const std::string file = test::modelPath(GetParam());
  const test::CliRun info = runMotionlod({"info", file, "--json"});
  ASSERT_EQ(info.status, 0) << info.err;
  const nlohmann::json described = nlohmann::json::parse(info.out);
  double originalVertices = 0.0;
  for (const nlohmann::json& mesh : described["meshes"])
    if (mesh["bones"].get<int>() > 0)
      originalVertices += mesh["vertices"].get<double>();
  ASSERT_GT(originalVertices, 0.0) << "a skinned mesh";
  const test::CliRun run = runMotionlod({"bench-crowd", file, "--scene", "--agents", "12", "--frames", "3", "--levels",
                                         "3", "--repetitions", "1", "--layout", "scattered", "--json"});
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json doc = nlohmann::json::parse(run.out);
  for (const char* key : {"agents", "frames", "threads", "levels", "configurations", "speedup"})
    EXPECT_TRUE(doc.contains(key)) << key;
  EXPECT_EQ(doc["agents"], 12);
  EXPECT_EQ(doc["frames"], 3);
  EXPECT_EQ(doc["threads"], 1);
  const nlohmann::json& levels = doc["levels"];
  ASSERT_EQ(levels.size(), 3u);
  int agents = 0;
  for (const nlohmann::json& level : levels) {
    for (const char* key :
         {"name", "threshold", "mesh_ratio", "triangles", "vertices", "joints", "switch_distance_m", "agents"})
      EXPECT_TRUE(level.contains(key)) << key;
    agents += level["agents"].get<int>();
  }
  EXPECT_EQ(agents, 12) << "every agent at one level";
  EXPECT_EQ(levels[0]["vertices"].get<double>(), originalVertices);
  EXPECT_EQ(levels[0]["joints"].get<std::size_t>(), described["joints"].size());
  EXPECT_EQ(levels[0]["mesh_ratio"], 1.0);
  const nlohmann::json& configurations = doc["configurations"];
  for (const char* name : {"none", "skeletal", "mesh", "both"}) {
    ASSERT_TRUE(configurations.contains(name)) << name;
    const nlohmann::json& c = configurations[name];
    for (const char* key : {"frame_ms", "pose_ms", "skin_ms", "joints_evaluated", "vertices_skinned"})
      EXPECT_TRUE(c.contains(key)) << name << " " << key;
    EXPECT_GT(c["frame_ms"].get<double>(), 0.0) << name;
    EXPECT_NEAR(c["frame_ms"].get<double>(), c["pose_ms"].get<double>() + c["skin_ms"].get<double>(), 1e-9) << name;
  }
  // none and skeletal skin the original mesh on every agent; mesh and both the levels'
  EXPECT_EQ(configurations["none"]["vertices_skinned"].get<double>(), 12.0 * originalVertices);
  EXPECT_EQ(configurations["skeletal"]["vertices_skinned"].get<double>(), 12.0 * originalVertices);
  EXPECT_EQ(configurations["mesh"]["vertices_skinned"], configurations["both"]["vertices_skinned"]);
  double levelVertices = 0.0;
  for (const nlohmann::json& level : levels)
    levelVertices += level["agents"].get<double>() * level["vertices"].get<double>();
  EXPECT_EQ(configurations["both"]["vertices_skinned"].get<double>(), levelVertices);
  for (const char* name : {"skeletal", "mesh", "both"})
    EXPECT_NEAR(doc["speedup"][name].get<double>(),
                configurations["none"]["frame_ms"].get<double>() / configurations[name]["frame_ms"].get<double>(), 1e-9)
        << name;
}
INSTANTIATE_TEST_SUITE_P(Characters, SceneJson, ::testing::ValuesIn(test::fixtureCharacters("animated")),
                         test::fixtureName);

// Guards the clip figures of each side (issue 25, item 5): clip_bytes, what the side's
// evaluator reads for its clip (> 0), and bytes_per_second = clip_bytes / the clip's
// duration; at a large threshold the LOD's clip is no larger than full detail's. With
// --no-skinning on a character, nothing is skinned: no skinning figures.
TEST(CliBenchCrowd, ClipBytesPerSide) {
  const test::CliRun run =
      runMotionlod({"bench-crowd", test::modelPath("BVH/01_01.bvh"), "--characters", "4", "--frames", "2",
                    "--threshold", "300", "--unit-scale", "cmu", "--repetitions", "1", "--json"});
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json doc = nlohmann::json::parse(run.out);
  const double seconds = doc["clip_seconds"].get<double>();
  EXPECT_GT(seconds, 20.0) << "CMU 01_01 plays 22.9 s";
  for (const char* side : {"full", "lod"}) {
    const nlohmann::json& figures = doc[side];
    const double bytes = figures["clip_bytes"].get<double>();
    EXPECT_GT(bytes, 0.0) << side;
    EXPECT_NEAR(figures["bytes_per_second"].get<double>(), bytes / seconds, 1e-9 * bytes) << side;
  }
  EXPECT_EQ(doc["full"]["clip_bytes"], doc["memory"]["full_bytes"]);
  EXPECT_EQ(doc["lod"]["clip_bytes"], doc["memory"]["lod_bytes"]);
  EXPECT_LE(doc["lod"]["clip_bytes"].get<std::int64_t>(), doc["full"]["clip_bytes"].get<std::int64_t>());

  const test::CliRun poseOnly =
      runMotionlod({"bench-crowd", test::modelPath("X/BCN_Epileptic.X"), "--characters", "4", "--frames", "2",
                    "--threshold", "50", "--repetitions", "1", "--no-skinning", "--json"});
  ASSERT_EQ(poseOnly.status, 0) << poseOnly.err;
  const nlohmann::json pose = nlohmann::json::parse(poseOnly.out);
  EXPECT_FALSE(pose.contains("skinning")) << "nothing skinned";
  EXPECT_GT(pose["full"]["clip_bytes"].get<double>(), 0.0);
}

// Guards the scene's clip and cost figures (issue 25, item 5): per configuration clip_bytes
// and bytes_per_second (none and mesh play level 0's motion alone, so they read the same
// bytes); per level agent_cost, the frame of every agent at the level over every agent at
// LOD0 (1 at LOD0, > 0 everywhere); --no-skinning skins nothing (skin_ms 0, frame_ms = pose_ms).
TEST(CliBenchCrowd, SceneClipBytesAgentCostsAndPoseOnly) {
  for (const bool skin : {true, false}) {
    SCOPED_TRACE(skin ? "skinned" : "--no-skinning");
    std::vector<std::string> arguments = {"bench-crowd", test::modelPath("X/BCN_Epileptic.X"),
                                          "--scene",     "--agents",
                                          "6",           "--frames",
                                          "2",           "--levels",
                                          "3",           "--repetitions",
                                          "1",           "--json"};
    if (!skin)
      arguments.push_back("--no-skinning");
    const test::CliRun run = runMotionlod(arguments);
    ASSERT_EQ(run.status, 0) << run.err;
    const nlohmann::json doc = nlohmann::json::parse(run.out);
    EXPECT_EQ(doc["budget_skinning"], "gpu") << "the default";
    EXPECT_EQ(doc["cpu_skinning"], skin);
    const double seconds = doc["clip_seconds"].get<double>();
    ASSERT_GT(seconds, 0.0);
    const nlohmann::json& levels = doc["levels"];
    ASSERT_GE(levels.size(), 2u);
    EXPECT_EQ(levels[0]["agent_cost"], 1.0);
    for (const nlohmann::json& level : levels) {
      EXPECT_GT(level["agent_cost"].get<double>(), 0.0) << level["name"];
      EXPECT_GT(level["all_agents_frame_ms"].get<double>(), 0.0) << level["name"];
    }
    const nlohmann::json& configurations = doc["configurations"];
    for (const char* name : {"none", "skeletal", "mesh", "both"}) {
      const nlohmann::json& c = configurations[name];
      const double bytes = c["clip_bytes"].get<double>();
      EXPECT_GT(bytes, 0.0) << name;
      EXPECT_NEAR(c["bytes_per_second"].get<double>(), bytes / seconds, 1e-9 * bytes) << name;
      if (!skin) {
        EXPECT_EQ(c["skin_ms"], 0.0) << name;
        EXPECT_EQ(c["frame_ms"], c["pose_ms"]) << name;
      } else {
        EXPECT_GT(c["skin_ms"].get<double>(), 0.0) << name;
      }
    }
    EXPECT_EQ(configurations["mesh"]["clip_bytes"], configurations["none"]["clip_bytes"]);
  }
}

// Guards --skinning (issue 25, item 4): the generated set's skinning is said in the JSON, a
// CPU-skinned set gives its motion less of each level's deviation (thresholds no higher than
// the GPU's), and a value other than gpu or cpu, or --skinning without --scene, is exit 2
// with the reason.
TEST(CliBenchCrowd, SkinningOptionOfTheScene) {
  const auto scene = [](const std::string& skinning) {
    return runMotionlod({"bench-crowd", test::modelPath("X/BCN_Epileptic.X"), "--scene", "--agents", "2", "--frames",
                         "1", "--levels", "3", "--repetitions", "1", "--skinning", skinning, "--json"});
  };
  const test::CliRun cpu = scene("cpu");
  ASSERT_EQ(cpu.status, 0) << cpu.err;
  const test::CliRun gpu = scene("gpu");
  ASSERT_EQ(gpu.status, 0) << gpu.err;
  const nlohmann::json cpuDoc = nlohmann::json::parse(cpu.out), gpuDoc = nlohmann::json::parse(gpu.out);
  EXPECT_EQ(cpuDoc["budget_skinning"], "cpu");
  EXPECT_EQ(gpuDoc["budget_skinning"], "gpu");
  double cpuTop = 0.0, gpuTop = 0.0;
  for (const nlohmann::json& level : cpuDoc["levels"])
    cpuTop = std::max(cpuTop, level["threshold"].get<double>());
  for (const nlohmann::json& level : gpuDoc["levels"])
    gpuTop = std::max(gpuTop, level["threshold"].get<double>());
  EXPECT_LT(cpuTop, gpuTop) << "5% of the deviation against a half";

  const test::CliRun bad = scene("GPU");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("--skinning"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("'GPU' is neither gpu nor cpu"), std::string::npos) << bad.err;
  EXPECT_TRUE(bad.out.empty());
  const test::CliRun noScene = runMotionlod({"bench-crowd", test::modelPath("BVH/01_01.bvh"), "--threshold", "50",
                                             "--characters", "2", "--frames", "1", "--skinning", "cpu"});
  EXPECT_EQ(noScene.status, 2);
  EXPECT_NE(noScene.err.find("--skinning applies to --scene"), std::string::npos) << noScene.err;
}

// Guards the readable table without --json, and the scene's bad input: a file without a
// skinned mesh, a motion file that does not exist, a layout that is not one.
TEST(CliBenchCrowd, SceneTableAndBadInput) {
  const test::CliRun table = runMotionlod({"bench-crowd", test::modelPath("X/BCN_Epileptic.X"), "--scene", "--agents",
                                           "4", "--frames", "2", "--levels", "2", "--repetitions", "1"});
  ASSERT_EQ(table.status, 0) << table.err;
  for (const char* word : {"none", "skeletal", "mesh", "both", "frame ms", "speedup"})
    EXPECT_NE(table.out.find(word), std::string::npos) << word << "\n" << table.out;
  const test::CliRun bvh = runMotionlod({"bench-crowd", test::modelPath("BVH/01_01.bvh"), "--scene"});
  EXPECT_EQ(bvh.status, 2);
  EXPECT_NE(bvh.err.find("error: " + test::modelPath("BVH/01_01.bvh") + ": "), std::string::npos) << bvh.err;
  EXPECT_TRUE(bvh.out.empty());
  const test::CliRun motion = runMotionlod(
      {"bench-crowd", test::modelPath("X/BCN_Epileptic.X"), "--scene", "--motion", "/nonexistent/walk.bvh"});
  EXPECT_EQ(motion.status, 2);
  EXPECT_NE(motion.err.find("error: /nonexistent/walk.bvh: "), std::string::npos) << motion.err;
  const test::CliRun layout =
      runMotionlod({"bench-crowd", test::modelPath("X/BCN_Epileptic.X"), "--scene", "--layout", "ring"});
  EXPECT_EQ(layout.status, 2);
  const test::CliRun noThreshold = runMotionlod({"bench-crowd", test::modelPath("BVH/01_01.bvh")});
  EXPECT_EQ(noThreshold.status, 2);
  EXPECT_NE(noThreshold.err.find("--threshold"), std::string::npos) << noThreshold.err;
}

} // namespace
} // namespace mlod
