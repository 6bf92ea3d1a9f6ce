// The command-line contract of docs/architecture.md section 6 for `--version` and `info`.

#include "cli_runner.h"
#include "test_files.h"

#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace mlod {
namespace {

using test::runMotionlod;

// Guards `motionlod --version`.
TEST(Cli, Version) {
  const test::CliRun run = runMotionlod({"--version"});
  EXPECT_EQ(run.status, 0);
  EXPECT_NE(run.out.find("motionlod 0.1.0"), std::string::npos) << run.out;
}

// Guards `info` on the CMU clip: the header's 2,752 frames, 38 joints, the table layout.
TEST(Cli, InfoPrintsCounts) {
  const test::CliRun run = runMotionlod({"info", test::modelPath("BVH/01_01.bvh"), "--unit-scale", "cmu"});
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_NE(run.out.find("2752 frames"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("38 joints"), std::string::npos);
  EXPECT_NE(run.out.find("5.64444 cm per file unit (option)"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("EndSite_Head (no rotation channel)"), std::string::npos);
}

// Guards `info --json`: one JSON document with joints (name, parent), clips, meshes, unit.
TEST(Cli, InfoJson) {
  const test::CliRun run = runMotionlod({"info", test::modelPath("X/BCN_Epileptic.X"), "--json"});
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json doc = nlohmann::json::parse(run.out);
  EXPECT_EQ(doc["joints"].size(), 54u);
  EXPECT_EQ(doc["clips"][0]["frames"], 100);
  EXPECT_EQ(doc["clips"][0]["fps"], 30.0);
  EXPECT_EQ(doc["meshes"][0]["vertices"], 3014);
  EXPECT_EQ(doc["meshes"][0]["triangles"], 5126);
  EXPECT_EQ(doc["meshes"][0]["bones"], 54);
  // The file states no unit: guessed as metres (the issue: read at 1 cm per unit it was a
  // 1.8 cm character), and said to be guessed, with the height it gives.
  EXPECT_EQ(doc["unit_scale"], 100.0);
  EXPECT_EQ(doc["unit_source"], "guessed");
  EXPECT_GT(doc["height_cm"].get<double>(), 170.0);
  EXPECT_LT(doc["height_cm"].get<double>(), 190.0);
  EXPECT_TRUE(doc["joints"][0]["parent"].is_null());
  // --unit-scale overrides the guess.
  const test::CliRun chosen =
      runMotionlod({"info", test::modelPath("X/BCN_Epileptic.X"), "--json", "--unit-scale", "cm"});
  ASSERT_EQ(chosen.status, 0) << chosen.err;
  const nlohmann::json option = nlohmann::json::parse(chosen.out);
  EXPECT_EQ(option["unit_scale"], 1.0);
  EXPECT_EQ(option["unit_source"], "option");
  EXPECT_LT(option["height_cm"].get<double>(), 2.0);
  // The human output prints the height.
  const test::CliRun text = runMotionlod({"info", test::modelPath("X/BCN_Epileptic.X")});
  EXPECT_NE(text.out.find("unit:     100 cm per file unit (guessed)"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("height:   181."), std::string::npos) << text.out;
}

// Guards the error contract: "error: FILE: reason" on stderr, exit 2, nothing on stdout.
TEST(Cli, BadFilesExitTwoWithMessage) {
  const std::string empty = test::writeTemp("empty.bvh", "");
  const std::string garbage = test::writeTemp("garbage.fbx", std::string(2048, '\x07'));
  const std::string lying = test::writeTemp(
      "lying.bvh", test::makeBvh("Xposition Yposition Zposition Zrotation Yrotation Xrotation",
                                 "Zrotation Yrotation Xrotation", 50, "0.01", "0 0 0 0 0 0 0 0 0\n"));
  for (const std::string& file : {empty, garbage, lying, std::string("/no/such/file.bvh")}) {
    SCOPED_TRACE(file);
    const test::CliRun run = runMotionlod({"info", file});
    EXPECT_EQ(run.status, 2);
    EXPECT_EQ(run.err.rfind("error: " + file + ": ", 0), 0u) << run.err;
    EXPECT_TRUE(run.out.empty()) << run.out;
  }
}

// Guards a file that crashes or exhausts the importer: the CLI survives and reports it.
TEST(Cli, RunawayImportIsReported) {
  const test::CliRun run =
      runMotionlod({"info", test::modelPath("invalid/OutOfMemory.off"), "--import-timeout", "5"});
  EXPECT_EQ(run.status, 2);
  EXPECT_EQ(run.err.rfind("error: ", 0), 0u) << run.err;
}

// Guards a file that makes Assimp segfault (found by libFuzzer): exit 2 with the reason.
TEST(Cli, ImporterCrashIsReported) {
  const test::CliRun run = runMotionlod({"info", test::dataPath("bad/assimp_x_crash.x")});
  EXPECT_EQ(run.status, 2);
  EXPECT_NE(run.err.find("the importer crashed on this file (signal 11"), std::string::npos) << run.err;
}

// Guards argument errors: a bad unit scale and a missing command exit 2.
TEST(Cli, BadArguments) {
  const test::CliRun unit = runMotionlod({"info", test::modelPath("BVH/01_01.bvh"), "--unit-scale", "-3"});
  EXPECT_EQ(unit.status, 2);
  EXPECT_NE(unit.err.find("--unit-scale"), std::string::npos) << unit.err;
  EXPECT_EQ(runMotionlod({}).status, 2);
  EXPECT_EQ(runMotionlod({"frobnicate"}).status, 2);
}

// A project at `folder`/p.mlod (core/project.h's version 3) with one asset at `assetPath`.
std::string projectWithAsset(const std::filesystem::path& folder, const std::string& assetPath) {
  const nlohmann::json level = {{"name", "LOD0"},          {"threshold", 0},     {"mesh_ratio", 1},
                                {"switch_distance_cm", 0}, {"pixel_error", 0},   {"screen_size_pixels", 0},
                                {"motion_error_cm", 0},    {"mesh_error_cm", 0}, {"triangles", 0},
                                {"active_joints", 0}};
  const nlohmann::json project = {{"format", "motionlod-project"},
                                  {"version", 3},
                                  {"alpha", 5},
                                  {"mode", "greedy"},
                                  {"lods",
                                   {{"projection", {{"vertical_fov_degrees", 60}, {"viewport_height_pixels", 1080}}},
                                    {"bounding_radius_cm", 0},
                                    {"levels", {level}}}},
                                  {"assets", {{{"path", assetPath}, {"joints", nlohmann::json::object()}}}}};
  const std::filesystem::path file = folder / "p.mlod";
  std::ofstream(file) << project.dump();
  return file.string();
}

// Guards `info PROJECT --json` listing the levels each asset plays with (issue 26, item 7:
// it listed the project's set alone): a character's own set ("own"), the project's for a
// character without one, and for a motion mapped onto a character that character's set.
TEST(Cli, InfoJsonListsEachAssetsLevels) {
  namespace fs = std::filesystem;
  const fs::path dir = test::freshFolder("cli", "info_levels");
  const auto levelJson = [](const std::string& name, double threshold, double ratio, double cm) {
    return nlohmann::json{
        {"name", name},     {"threshold", threshold},  {"mesh_ratio", ratio},  {"switch_distance_cm", cm},
        {"pixel_error", 0}, {"screen_size_pixels", 0}, {"motion_error_cm", 0}, {"mesh_error_cm", 0},
        {"triangles", 0},   {"active_joints", 0}};
  };
  const auto lods = [](nlohmann::json levels) {
    return nlohmann::json{{"projection", {{"vertical_fov_degrees", 60}, {"viewport_height_pixels", 1080}}},
                          {"bounding_radius_cm", 0},
                          {"levels", std::move(levels)}};
  };
  const nlohmann::json shared =
      lods({levelJson("LOD0", 0, 1, 0), levelJson("LOD1", 5, 1, 0), levelJson("LOD2", 50, 1, 0)});
  const nlohmann::json own = lods({levelJson("LOD0", 0, 1, 0), levelJson("Close", 2, 0.5, 900),
                                   levelJson("Away", 30, 0.1, 4700), levelJson("Gone", 300, 0.05, 9000)});
  const nlohmann::json table = {{"format", "motionlod-mapping"},
                                {"version", 1},
                                {"motion", "01_01.bvh"},
                                {"character", "BCN_Epileptic.X"},
                                {"pairs", {{{"character", "B_Root_Pelvis_L"}, {"motion", "Hips"}}}}};
  const nlohmann::json project = {
      {"format", "motionlod-project"},
      {"version", 4},
      {"alpha", 5},
      {"mode", "greedy"},
      {"lods", shared},
      {"assets",
       {{{"path", test::modelPath("X/BCN_Epileptic.X")}, {"joints", nlohmann::json::object()}, {"lods", own}},
        {{"path", test::modelPath("BVH/01_01.bvh")}, {"unit_scale", 2.54 / 0.45}, {"joints", nlohmann::json::object()}},
        {{"path", test::modelPath("X/Testwuson.X")}, {"joints", nlohmann::json::object()}}}},
      {"mappings", {{{"motion", 1}, {"character", 0}, {"table", table}}}}};
  const fs::path file = dir / "characters.mlod";
  std::ofstream(file) << project.dump();
  const test::CliRun run = runMotionlod({"info", file.string(), "--json"});
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json doc = nlohmann::json::parse(run.out);
  ASSERT_EQ(doc["assets"].size(), 3u);
  const auto names = [](const nlohmann::json& levels) {
    std::vector<std::string> out;
    for (const nlohmann::json& level : levels)
      out.push_back(level["name"]);
    return out;
  };
  const std::vector<std::string> ownNames{"LOD0", "Close", "Away", "Gone"};
  EXPECT_EQ(doc["assets"][0]["levels_of"], "own");
  EXPECT_EQ(names(doc["assets"][0]["levels"]), ownNames);
  EXPECT_EQ(doc["assets"][0]["levels"][2]["mesh_ratio"], 0.1);
  EXPECT_EQ(doc["assets"][0]["levels"][2]["switch_distance_cm"], 4700);
  EXPECT_EQ(doc["assets"][1]["levels_of"], "asset 0"); // the motion plays with its character's
  EXPECT_EQ(names(doc["assets"][1]["levels"]), ownNames);
  EXPECT_EQ(doc["assets"][2]["levels_of"], "project");
  EXPECT_EQ(names(doc["assets"][2]["levels"]), (std::vector<std::string>{"LOD0", "LOD1", "LOD2"}));
  EXPECT_EQ(names(doc["levels"]), (std::vector<std::string>{"LOD0", "LOD1", "LOD2"}));
  // the human output says it too
  const test::CliRun text = runMotionlod({"info", file.string()});
  ASSERT_EQ(text.status, 0) << text.err;
  EXPECT_NE(text.out.find("its own LOD set, 4 levels"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("plays with asset 0's LOD set"), std::string::npos) << text.out;
}

// Guards issue 29's `../../../../../../etc/passwd` in a project: it was followed and read.
// Commands that read projects refuse a relative asset path that leaves the project's folder
// (exit 2, the error naming the path) unless --allow-outside-assets; a relative path inside
// the folder and an absolute path anywhere still load.
TEST(Cli, ProjectAssetsOutsideTheFolderAreRefused) {
  namespace fs = std::filesystem;
  const fs::path dir = test::freshFolder("cli", "outside_assets");
  fs::create_directories(dir / "clips");
  fs::copy_file(test::modelPath("BVH/01_01.bvh"), dir / "clips" / "a.bvh");
  const std::string climbing = "../../../../../../etc/passwd";
  const std::string project = projectWithAsset(dir, climbing);
  for (const char* command : {"info", "simplify"}) {
    SCOPED_TRACE(command);
    const test::CliRun run = runMotionlod({command, project});
    EXPECT_EQ(run.status, 2);
    EXPECT_EQ(
        run.err.rfind("error: " + project + ": asset 0 ('" + climbing + "') leads outside the project's folder", 0), 0u)
        << run.err;
    EXPECT_TRUE(run.out.empty()) << run.out;
  }
  // allowed, the path is followed: the import (not the project) refuses /etc/passwd
  const test::CliRun allowed = runMotionlod({"info", project, "--allow-outside-assets", "--json"});
  EXPECT_EQ(allowed.status, 2);
  EXPECT_EQ(allowed.err.find("leads outside"), std::string::npos) << allowed.err;
  EXPECT_EQ(nlohmann::json::parse(allowed.out)["assets"][0]["resolved"], "/etc/passwd");

  for (const std::string& path : {std::string("clips/a.bvh"), (dir / "clips" / "a.bvh").string()}) {
    SCOPED_TRACE(path);
    const test::CliRun run = runMotionlod({"info", projectWithAsset(dir, path), "--json"});
    EXPECT_EQ(run.status, 0) << run.err;
    EXPECT_EQ(nlohmann::json::parse(run.out)["assets"][0]["asset"]["joints"].size(), 38u) << run.out;
  }
}

} // namespace
} // namespace mlod
