// The command-line contract of `motionlod plugins [--json]`, `motionlod export` and
// `motionlod info FILE.mlodb`: every available exporter writes a file from a file and from a
// project, bad plugin ids, options and levels are exit 2 with `error: FILE: reason`, an
// unwritable output is exit 1 and leaves nothing behind, a corrupt bundle is refused.

#include "cli_runner.h"
#include "test_files.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <unistd.h>

namespace mlod {
namespace {

namespace fs = std::filesystem;
using test::keysOf;
using test::filesIn;
using test::runMotionlod;

fs::path freshFolder(const std::string& name) { return test::freshFolder("export", name); }


nlohmann::json pluginList() {
  const test::CliRun run = runMotionlod({"plugins", "--json"});
  EXPECT_EQ(run.status, 0) << run.err;
  return nlohmann::json::parse(run.out);
}

const std::string kSample = MLOD_SAMPLE;

TEST(CliPlugins, JsonListsTheBuiltExporters) {
  const nlohmann::json doc = pluginList();
  EXPECT_EQ(keysOf(doc), (std::vector<std::string>{"failed", "plugins", "search_path"}));
  std::vector<std::string> ids;
  for (const nlohmann::json& plugin : doc["plugins"]) {
    EXPECT_EQ(keysOf(plugin), (std::vector<std::string>{"file", "id", "name", "options", "suffixes", "version"}));
    EXPECT_FALSE(plugin["suffixes"].empty());
    for (const nlohmann::json& option : plugin["options"])
      EXPECT_EQ(keysOf(option),
                (std::vector<std::string>{"choices", "default", "help", "key", "maximum", "minimum", "type"}));
    ids.push_back(plugin["id"]);
  }
  EXPECT_NE(std::find(ids.begin(), ids.end(), "bundle"), ids.end());
  EXPECT_TRUE(doc["failed"].empty()) << doc["failed"].dump();

  const test::CliRun text = runMotionlod({"plugins"});
  EXPECT_EQ(text.status, 0);
  EXPECT_NE(text.out.find("bundle"), std::string::npos) << text.out;
}

TEST(CliPlugins, BrokenPluginsAreReportedNotFatal) {
  ::setenv("MOTIONLOD_PLUGIN_PATH", MLOD_TEST_PLUGIN_DIR, 1);
  const test::CliRun run = runMotionlod({"plugins", "--json"});
  ::unsetenv("MOTIONLOD_PLUGIN_PATH");
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json doc = nlohmann::json::parse(run.out);
  std::vector<std::string> failedFiles;
  for (const nlohmann::json& failure : doc["failed"]) {
    EXPECT_EQ(keysOf(failure), (std::vector<std::string>{"file", "reason"}));
    failedFiles.push_back(fs::path(failure["file"].get<std::string>()).filename().string());
  }
  std::sort(failedFiles.begin(), failedFiles.end());
  EXPECT_EQ(failedFiles, (std::vector<std::string>{"libmotionlod_testbroken.so", "libmotionlod_testoldversion.so",
                                                   "libmotionlod_testwrongiid.so"}));
  bool good = false, bundle = false;
  for (const nlohmann::json& plugin : doc["plugins"]) {
    good = good || plugin["id"] == "testgood";
    bundle = bundle || plugin["id"] == "bundle";
  }
  EXPECT_TRUE(good && bundle); // the environment's folder first, then the executable's
}

// Every exporter the build made writes a non-empty file from a BVH and from a skinned
// character, and nothing else lands beside it but what the exporter documents.
TEST(CliExport, EveryPluginExportsFilesAndCharacters) {
  const nlohmann::json plugins = pluginList()["plugins"];
  ASSERT_FALSE(plugins.empty());
  const struct {
    std::string file, unit;
  } inputs[] = {{kSample, "cmu"}, {test::modelPath("X/BCN_Epileptic.X"), "m"}};
  for (const nlohmann::json& plugin : plugins) {
    const std::string id = plugin["id"];
    const std::string suffix = plugin["suffixes"][0];
    for (const auto& input : inputs) {
      SCOPED_TRACE(id + " " + input.file);
      const fs::path dir = freshFolder("each_" + id);
      const std::string out = (dir / ("out." + suffix)).string();
      const test::CliRun run = runMotionlod(
          {"export", input.file, "--unit-scale", input.unit, "--plugin", id, "-o", out, "--json"});
      ASSERT_EQ(run.status, 0) << run.err;
      const nlohmann::json doc = nlohmann::json::parse(run.out);
      EXPECT_EQ(keysOf(doc), (std::vector<std::string>{"bytes", "input", "levels", "message", "ok", "options",
                                                       "output", "plugin", "seconds"}));
      EXPECT_TRUE(doc["ok"].get<bool>());
      EXPECT_EQ(doc["levels"], 4); // the default LOD set of a file
      EXPECT_GT(doc["bytes"].get<std::int64_t>(), 0);
      EXPECT_EQ(doc["bytes"].get<std::int64_t>(), std::int64_t(fs::file_size(out)));
      for (const std::string& name : filesIn(dir))
        EXPECT_NE(name[0], '.') << "a temporary file was left: " << name;
    }
  }
}

TEST(CliExport, BundleLevelsAndInfo) {
  const fs::path dir = freshFolder("levels");
  const std::string out = (dir / "sample.mlodb").string();
  const test::CliRun run = runMotionlod(
      {"export", kSample, "--unit-scale", "cmu", "--plugin", "bundle", "-o", out, "--levels", "0,2", "--option", "manifest=no"});
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(filesIn(dir), std::vector<std::string>{"sample.mlodb"});
  const test::CliRun info = runMotionlod({"info", out, "--json"});
  ASSERT_EQ(info.status, 0) << info.err;
  const nlohmann::json doc = nlohmann::json::parse(info.out);
  EXPECT_EQ(doc["format"], "motionlod-bundle");
  EXPECT_EQ(doc["version"], 2);
  ASSERT_EQ(doc["levels"].size(), 2u);
  EXPECT_EQ(doc["levels"][0]["index"], 0);
  EXPECT_EQ(doc["levels"][1]["index"], 2);
  EXPECT_EQ(doc["levels"][0]["clips"][0]["clusters"], 0);
  EXPECT_GT(doc["levels"][1]["clips"][0]["clusters"].get<int>(), 0);
  EXPECT_EQ(doc["bytes"].get<std::int64_t>(), std::int64_t(fs::file_size(out)));
  // what each level's clip costs at run time: fewer bytes at level 2 (frozen joints store one
  // key per cluster), per second of animation, quantized within the default precision
  for (const nlohmann::json& level : doc["levels"]) {
    const nlohmann::json& clip = level["clips"][0];
    const double seconds = (clip["frames"].get<double>() - 1.0) / clip["fps"].get<double>();
    EXPECT_NEAR(clip["bytes_per_second"].get<double>(), clip["bytes"].get<double>() / seconds, 1e-6);
    EXPECT_EQ(clip["precision_cm"].get<double>(), 0.01);
    EXPECT_GT(clip["encoded_error_cm"].get<double>(), 0.0);
    EXPECT_LE(clip["encoded_error_cm"].get<double>(), clip["precision_cm"].get<double>());
    EXPECT_EQ(clip["blend_frames"], 4); // the bundle plugin's default
    // the file holds what the evaluator reads (docs/bundle-format.md): within 10%
    EXPECT_NEAR(clip["bytes_in_file"].get<double>() / clip["bytes"].get<double>(), 1.0, 0.1);
  }
  EXPECT_LT(doc["levels"][1]["clips"][0]["bytes"].get<std::int64_t>(),
            doc["levels"][0]["clips"][0]["bytes"].get<std::int64_t>());
  const test::CliRun text = runMotionlod({"info", out});
  EXPECT_EQ(text.status, 0);
  EXPECT_NE(text.out.find("Motion LOD runtime bundle, version 2"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("bytes/s, blend 4 frames, error bound "), std::string::npos) << text.out;
}

// The file's own unit (BVH: 1 cm per unit) makes the CMU skeleton small enough that its
// first generated level deviates by nothing; that level switches in at the bounding radius,
// where its pixel figure must be 0, not infinite (the default LOD set used to be refused:
// "level 1: pixel figures must be finite").
TEST(CliExport, DefaultLodSetOfASkeletonInItsOwnUnit) {
  const fs::path dir = freshFolder("own_unit");
  const std::string out = (dir / "01_01.mlodb").string();
  const test::CliRun run = runMotionlod({"export", test::modelPath("BVH/01_01.bvh"), "--plugin", "bundle", "-o", out});
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json info = nlohmann::json::parse(runMotionlod({"info", out, "--json"}).out);
  ASSERT_EQ(info["levels"].size(), 4u);
}

TEST(CliExport, CorruptBundleIsRefused) {
  const fs::path dir = freshFolder("corrupt");
  const std::string out = (dir / "c.mlodb").string();
  ASSERT_EQ(runMotionlod({"export", kSample, "--unit-scale", "cmu", "--plugin", "bundle", "-o", out}).status, 0);
  const std::uintmax_t size = fs::file_size(out);
  fs::resize_file(out, size - 100);
  const test::CliRun truncated = runMotionlod({"info", out});
  EXPECT_EQ(truncated.status, 2);
  EXPECT_EQ(truncated.err.rfind("error: " + out + ": truncated", 0), 0u) << truncated.err;
  { // a flipped byte in the middle
    std::fstream file(out, std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(std::streamoff(size / 2));
    file.put('\x7f');
  }
  fs::resize_file(out, size);
  const test::CliRun flipped = runMotionlod({"info", out, "--json"});
  EXPECT_EQ(flipped.status, 2);
  EXPECT_NE(flipped.err.find("error: " + out + ": "), std::string::npos) << flipped.err;
  EXPECT_TRUE(flipped.out.empty());
}

TEST(CliExport, BadArgumentsAreExit2) {
  const fs::path dir = freshFolder("bad");
  const std::string out = (dir / "x.mlodb").string();
  const struct {
    std::vector<std::string> arguments;
    std::string reason;
  } cases[] = {
      {{"--plugin", "nosuch"}, "no exporter plugin 'nosuch' (available: "},
      {{"--plugin", "bundle", "--option", "nosuch=1"}, "plugin bundle: unknown option 'nosuch'"},
      {{"--plugin", "bundle", "--option", "meshes=maybe"}, "option 'meshes': 'maybe' is not a bool"},
      {{"--plugin", "bundle", "--option", "meshes"}, "is not key=value"},
      {{"--plugin", "bundle", "--levels", "0,x"}, "--levels '0,x': 'x' is not a level index"},
      {{"--plugin", "bundle", "--levels", "0,7"}, "level 7 does not exist (the LOD set has 4 levels"},
      {{"--plugin", "bundle", "--levels", "1,1"}, "level 1 is named twice"},
      {{"--plugin", "bundle", "--unit-scale", "parsec"}, "--unit-scale 'parsec'"},
  };
  for (const auto& c : cases) {
    std::vector<std::string> arguments = {"export", kSample, "-o", out};
    arguments.insert(arguments.end(), c.arguments.begin(), c.arguments.end());
    if (std::find(c.arguments.begin(), c.arguments.end(), "--unit-scale") == c.arguments.end()) {
      arguments.push_back("--unit-scale");
      arguments.push_back("cmu");
    }
    const test::CliRun run = runMotionlod(arguments);
    SCOPED_TRACE(c.reason);
    EXPECT_EQ(run.status, 2) << run.err;
    EXPECT_EQ(run.err.rfind("error: " + kSample + ": ", 0), 0u) << run.err;
    EXPECT_NE(run.err.find(c.reason), std::string::npos) << run.err;
  }
  const test::CliRun missing = runMotionlod({"export", "/no/such/file.bvh", "--plugin", "bundle", "-o", out});
  EXPECT_EQ(missing.status, 2);
  EXPECT_EQ(missing.err.rfind("error: /no/such/file.bvh: ", 0), 0u) << missing.err;
  // a mesh without a skeleton has no bundle (it exited 1 with the plugin's "no joint")
  const std::string spider = std::string(MLOD_ASSIMP_MODELS) + "/OBJ/spider.obj";
  const test::CliRun meshOnly = runMotionlod({"export", spider, "--plugin", "bundle", "-o", out});
  EXPECT_EQ(meshOnly.status, 2) << meshOnly.err;
  EXPECT_NE(meshOnly.err.find("error: " + spider + ": has no skeleton: a runtime bundle holds a skeleton"),
            std::string::npos)
      << meshOnly.err;
  EXPECT_TRUE(filesIn(dir).empty());
}

// Guards --skinning (issue 25, item 4): a value other than gpu or cpu is a parse error naming
// the two; it applies to a file's default LOD set only, so with a project (whose set keeps
// its own) or with --mesh-ratio (levels of the original motion) it is exit 2 with the reason.
// Nothing is written.
TEST(CliExport, SkinningIsGpuOrCpuForAFilesDefaultSet) {
  const fs::path dir = freshFolder("skinning");
  const std::string out = (dir / "x.mlodb").string();
  const test::CliRun bad = runMotionlod({"export", kSample, "--plugin", "bundle", "-o", out, "--skinning", "both"});
  EXPECT_EQ(bad.status, 2) << bad.err;
  EXPECT_NE(bad.err.find("--skinning"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("'both' is neither gpu nor cpu"), std::string::npos) << bad.err;
  const test::CliRun ratios =
      runMotionlod({"export", kSample, "--plugin", "bundle", "-o", out, "--skinning", "cpu", "--mesh-ratio", "0.5"});
  EXPECT_EQ(ratios.status, 2) << ratios.err;
  EXPECT_NE(ratios.err.find("error: " + kSample + ": --skinning applies to the default LOD set"), std::string::npos)
      << ratios.err;
  const nlohmann::json level0 = {
      {"name", "L0"},       {"threshold", 0.0},          {"mesh_ratio", 1.0},      {"switch_distance_cm", 0.0},
      {"pixel_error", 0.0}, {"screen_size_pixels", 0.0}, {"motion_error_cm", 0.0}, {"mesh_error_cm", 0.0},
      {"triangles", 0},     {"active_joints", 0}};
  const nlohmann::json project = {
      {"format", "motionlod-project"},
      {"version", 4},
      {"alpha", 5.0},
      {"mode", "greedy"},
      {"lods",
       {{"projection", {{"vertical_fov_degrees", 60.0}, {"viewport_height_pixels", 1080.0}}},
        {"bounding_radius_cm", 0.0},
        {"levels", {level0}}}},
      {"assets", {{{"path", kSample}, {"unit_scale", 2.54 / 0.45}, {"joints", nlohmann::json::object()}}}}};
  const fs::path file = dir / "p.mlod";
  std::ofstream(file) << project.dump(2);
  const test::CliRun onProject =
      runMotionlod({"export", file.string(), "--plugin", "bundle", "-o", out, "--skinning", "gpu"});
  EXPECT_EQ(onProject.status, 2) << onProject.err;
  EXPECT_NE(onProject.err.find("--skinning applies to a file's default LOD set; a project exports its own levels"),
            std::string::npos)
      << onProject.err;
  EXPECT_TRUE(filesIn(dir).size() == 1u) << "the project alone";
}

// The output's suffix says its format, as the Export dialog asks: a suffix that is not one
// of the plugin's (from its metadata), or none, is exit 2 before any work (no import; what is
// at the output stays as it was); the plugin's own suffix in any case is written. Before:
// `export --plugin gltf -o x.bundle` wrote a GLB named x.bundle and exited 0.
TEST(CliExport, OutputSuffixMustBeThePlugins) {
  const fs::path dir = freshFolder("suffix");
  const fs::path taken = dir / "x.bundle";
  std::ofstream(taken) << "someone's bundle";
  const struct {
    std::string plugin;
    fs::path output;
    std::string reason;
  } cases[] = {
      {"gltf", taken, "the gltf exporter writes .glb or .gltf files, not .bundle"},
      {"gltf", dir / "x", "the gltf exporter writes .glb or .gltf files, and the name has no suffix"},
      {"bundle", dir / "x.glb", "the bundle exporter writes .mlodb files, not .glb"},
      {"report", dir / "x.txt", "the report exporter writes .html, .csv or .json files, not .txt"},
      {"gltf", dir / "x.glb.bak", "the gltf exporter writes .glb or .gltf files, not .bak"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.reason);
    const test::CliRun run = runMotionlod(
        {"export", kSample, "--unit-scale", "cmu", "--plugin", c.plugin, "-o", c.output.string(), "--json"});
    EXPECT_EQ(run.status, 2) << run.err;
    EXPECT_EQ(run.err, "error: " + c.output.string() + ": " + c.reason + "\n");
    const nlohmann::json doc = nlohmann::json::parse(run.out);
    EXPECT_FALSE(doc["ok"].get<bool>());
    EXPECT_EQ(doc["seconds"]["import"].get<double>(), 0.0); // refused before the import
  }
  EXPECT_EQ(filesIn(dir), std::vector<std::string>{"x.bundle"});
  EXPECT_EQ(test::readText(taken.string()), "someone's bundle");
  const std::string upper = (dir / "x.GLB").string();
  const test::CliRun ok =
      runMotionlod({"export", kSample, "--unit-scale", "cmu", "--plugin", "gltf", "-o", upper, "-q"});
  EXPECT_EQ(ok.status, 0) << ok.err;
  EXPECT_GT(fs::file_size(upper), 0u);
}

TEST(CliExport, UnwritableOutputLeavesNothingAndSaysWhy) {
  const fs::path dir = freshFolder("unwritable");
  const std::string inMissingFolder = (dir / "no" / "such" / "x.mlodb").string();
  const test::CliRun run =
      runMotionlod({"export", kSample, "--unit-scale", "cmu", "--plugin", "bundle", "-o", inMissingFolder});
  EXPECT_EQ(run.status, 1);
  EXPECT_EQ(run.err.rfind("error: " + inMissingFolder + ": cannot write: the folder ", 0), 0u) << run.err;
  const fs::path folderAsOutput = dir / "taken.mlodb";
  fs::create_directory(folderAsOutput);
  const test::CliRun folder =
      runMotionlod({"export", kSample, "--unit-scale", "cmu", "--plugin", "bundle", "-o", folderAsOutput.string()});
  EXPECT_EQ(folder.status, 1);
  EXPECT_NE(folder.err.find("cannot write: it is a folder"), std::string::npos) << folder.err;
  EXPECT_EQ(filesIn(dir), std::vector<std::string>{"taken.mlodb"});
  EXPECT_TRUE(fs::is_empty(folderAsOutput));
}

// A project exports its own levels (not the default set) for the asset it has in view.
TEST(CliExport, ProjectGivesItsLevels) {
  const fs::path dir = freshFolder("project");
  nlohmann::json levels = nlohmann::json::array();
  const double thresholds[] = {0.0, 5.0, 50.0};
  for (int i = 0; i < 3; ++i)
    levels.push_back({{"name", "L" + std::to_string(i)}, {"threshold", thresholds[i]}, {"mesh_ratio", 1.0},
                      {"switch_distance_cm", 100.0 * i}, {"pixel_error", 0.0}, {"screen_size_pixels", 0.0},
                      {"motion_error_cm", 0.0}, {"mesh_error_cm", 0.0}, {"triangles", 0}, {"active_joints", 0}});
  const nlohmann::json project = {
      {"format", "motionlod-project"},
      {"version", 2},
      {"alpha", 5.0},
      {"mode", "greedy"},
      {"lods",
       {{"projection", {{"vertical_fov_degrees", 60.0}, {"viewport_height_pixels", 1080.0}}},
        {"bounding_radius_cm", 0.0},
        {"levels", levels}}},
      {"assets", {{{"path", kSample}, {"unit_scale", 2.54 / 0.45}, {"joints", nlohmann::json::object()}}}},
      {"mappings", nlohmann::json::array()},
      {"current", {{"asset", 0}, {"clip", 0}, {"level", 1}, {"joint", ""}}}};
  const fs::path file = dir / "p.mlod";
  std::ofstream(file) << project.dump(2);
  const std::string out = (dir / "p.mlodb").string();
  const test::CliRun run = runMotionlod({"export", file.string(), "--plugin", "bundle", "-o", out, "--json"});
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(nlohmann::json::parse(run.out)["levels"], 3);
  const nlohmann::json info = nlohmann::json::parse(runMotionlod({"info", out, "--json"}).out);
  ASSERT_EQ(info["levels"].size(), 3u);
  EXPECT_EQ(info["levels"][1]["name"], "L1");
  EXPECT_EQ(info["levels"][2]["threshold"], 50.0);
  EXPECT_EQ(info["levels"][2]["switch_distance_cm"], 200.0);

  // version 4: a character's own set is what it exports (issue 26, item 2), not the project's
  nlohmann::json version4 = project;
  version4["version"] = 4;
  version4["assets"][0]["lods"] = project["lods"];
  version4["assets"][0]["lods"]["levels"].erase(1);
  const fs::path file4 = dir / "p4.mlod";
  std::ofstream(file4) << version4.dump(2);
  const std::string out4 = (dir / "p4.mlodb").string();
  const test::CliRun own = runMotionlod({"export", file4.string(), "--plugin", "bundle", "-o", out4, "--json"});
  ASSERT_EQ(own.status, 0) << own.err;
  EXPECT_EQ(nlohmann::json::parse(own.out)["levels"], 2);
  const nlohmann::json ownInfo = nlohmann::json::parse(runMotionlod({"info", out4, "--json"}).out);
  ASSERT_EQ(ownInfo["levels"].size(), 2u);
  EXPECT_EQ(ownInfo["levels"][1]["name"], "L2");
  EXPECT_EQ(ownInfo["levels"][1]["threshold"], 50.0);
}

// A project whose motion in view (CMU 01_01) is assigned to a character (BCN_Epileptic):
// the character is exported, playing its own clip and the retargeted motion at every level.
TEST(CliExport, ProjectExportsTheCharacterWithItsMappedMotion) {
  const fs::path dir = freshFolder("mapped");
  nlohmann::json levels = nlohmann::json::array();
  const double thresholds[] = {0.0, 5.0, 50.0}, ratios[] = {1.0, 0.8, 0.5};
  for (int i = 0; i < 3; ++i)
    levels.push_back({{"name", "LOD" + std::to_string(i)}, {"threshold", thresholds[i]}, {"mesh_ratio", ratios[i]},
                      {"switch_distance_cm", 500.0 * i}, {"pixel_error", 0.0}, {"screen_size_pixels", 0.0},
                      {"motion_error_cm", 0.0}, {"mesh_error_cm", 0.0}, {"triangles", 0}, {"active_joints", 0}});
  const nlohmann::json mapping =
      nlohmann::json::parse(test::readText(std::string(MLOD_TEST_DATA_DIR) + "/mappings/cmu_01_01_to_bcn_epileptic.json"));
  const nlohmann::json project = {
      {"format", "motionlod-project"},
      {"version", 2},
      {"alpha", 5.0},
      {"mode", "greedy"},
      {"lods",
       {{"projection", {{"vertical_fov_degrees", 60.0}, {"viewport_height_pixels", 1080.0}}},
        {"bounding_radius_cm", 0.0},
        {"levels", levels}}},
      {"assets",
       {{{"path", test::modelPath("X/BCN_Epileptic.X")}, {"unit_scale", 100.0}, {"joints", nlohmann::json::object()}},
        {{"path", test::modelPath("BVH/01_01.bvh")}, {"unit_scale", 2.54 / 0.45}, {"joints", nlohmann::json::object()}}}},
      {"mappings", {{{"motion", 1}, {"character", 0}, {"table", mapping}}}},
      {"current", {{"asset", 1}, {"clip", 0}, {"level", 1}, {"joint", ""}}}};
  const fs::path file = dir / "mapped.mlod";
  std::ofstream(file) << project.dump(2);
  const std::string out = (dir / "mapped.mlodb").string();
  const test::CliRun run = runMotionlod({"export", file.string(), "--plugin", "bundle", "-o", out});
  ASSERT_EQ(run.status, 0) << run.err;
  const test::CliRun info = runMotionlod({"info", out, "--json"});
  ASSERT_EQ(info.status, 0) << info.err;
  const nlohmann::json doc = nlohmann::json::parse(info.out);
  EXPECT_EQ(doc["name"], "BCN_Epileptic");
  EXPECT_EQ(doc["joints"], 54);
  ASSERT_EQ(doc["levels"].size(), 3u);
  int previousTriangles = 1 << 30;
  for (const nlohmann::json& level : doc["levels"]) {
    ASSERT_EQ(level["clips"].size(), 2u) << level.dump(); // its own clip and the mapped CMU motion
    EXPECT_EQ(level["clips"][1]["frames"], 2752);
    ASSERT_TRUE(level["mesh"].is_object());
    EXPECT_LT(level["mesh"]["triangles"].get<int>(), previousTriangles);
    previousTriangles = level["mesh"]["triangles"].get<int>();
  }
  EXPECT_GT(doc["levels"][2]["clips"][1]["clusters"].get<int>(), doc["levels"][1]["clips"][1]["clusters"].get<int>());
}

// Issue 26: a project of two characters, each with its own set (BCN_Epileptic 3 levels, the
// CMU clip 01_01 mapped onto it; Testwuson 2 levels), the motion in view. `export` without
// --character exports the motion's character and says which of the two it is and how to pick
// the other; --character NAME (file name, stem or index) exports that one with its own set
// and the motions mapped onto it; an unknown name is exit 2 listing the characters; so is
// --character on a file or beside --asset. A batch job's "character" does the same.
TEST(CliExport, CharacterPicksWhichOfAProjectsCharactersIsExported) {
  const fs::path dir = freshFolder("characters");
  const auto levelsOf = [](std::vector<double> thresholds) {
    nlohmann::json levels = nlohmann::json::array();
    for (std::size_t i = 0; i < thresholds.size(); ++i)
      levels.push_back({{"name", "LOD" + std::to_string(i)},
                        {"threshold", thresholds[i]},
                        {"mesh_ratio", i == 0 ? 1.0 : 0.5},
                        {"switch_distance_cm", 500.0 * double(i)},
                        {"pixel_error", 0.0},
                        {"screen_size_pixels", 0.0},
                        {"motion_error_cm", 0.0},
                        {"mesh_error_cm", 0.0},
                        {"triangles", 0},
                        {"active_joints", 0}});
    return nlohmann::json{{"projection", {{"vertical_fov_degrees", 60.0}, {"viewport_height_pixels", 1080.0}}},
                          {"bounding_radius_cm", 0.0},
                          {"levels", levels}};
  };
  const nlohmann::json mapping = nlohmann::json::parse(
      test::readText(std::string(MLOD_TEST_DATA_DIR) + "/mappings/cmu_01_01_to_bcn_epileptic.json"));
  const nlohmann::json project = {
      {"format", "motionlod-project"},
      {"version", 4},
      {"alpha", 5.0},
      {"mode", "greedy"},
      {"lods", levelsOf({0.0, 5.0, 50.0, 100.0})},
      {"assets",
       {{{"path", test::modelPath("X/BCN_Epileptic.X")},
         {"unit_scale", 100.0},
         {"joints", nlohmann::json::object()},
         {"lods", levelsOf({0.0, 5.0, 50.0})}},
        {{"path", test::modelPath("BVH/01_01.bvh")}, {"unit_scale", 2.54 / 0.45}, {"joints", nlohmann::json::object()}},
        {{"path", test::modelPath("X/Testwuson.X")},
         {"unit_scale", 100.0},
         {"joints", nlohmann::json::object()},
         {"lods", levelsOf({0.0, 20.0})}}}},
      {"mappings", {{{"motion", 1}, {"character", 0}, {"table", mapping}}}},
      {"current", {{"asset", 1}, {"clip", 0}, {"level", 1}, {"joint", ""}}}};
  const fs::path file = dir / "two.mlod";
  std::ofstream(file) << project.dump(2);
  const auto info = [](const std::string& bundle) {
    const test::CliRun run = runMotionlod({"info", bundle, "--json"});
    EXPECT_EQ(run.status, 0) << run.err;
    return nlohmann::json::parse(run.out);
  };

  // by name: Testwuson with its own 2 levels and its own 3 clips (no motion is mapped onto it)
  const std::string wuson = (dir / "wuson.mlodb").string();
  const test::CliRun named = runMotionlod(
      {"export", file.string(), "--character", "Testwuson.X", "--plugin", "bundle", "-o", wuson, "--json"});
  ASSERT_EQ(named.status, 0) << named.err;
  EXPECT_EQ(nlohmann::json::parse(named.out)["character"], "Testwuson.X");
  const nlohmann::json wusonInfo = info(wuson);
  EXPECT_EQ(wusonInfo["name"], "Testwuson");
  ASSERT_EQ(wusonInfo["levels"].size(), 2u);
  EXPECT_EQ(wusonInfo["levels"][1]["threshold"], 20.0);
  EXPECT_EQ(wusonInfo["levels"][1]["clips"].size(), 3u);

  // without it: the motion in view's character, BCN, with its 3 levels and the mapped clip;
  // the output says which of the two and how to pick the other
  const std::string bcn = (dir / "bcn.mlodb").string();
  const test::CliRun byDefault = runMotionlod({"export", file.string(), "--plugin", "bundle", "-o", bcn, "-q"});
  ASSERT_EQ(byDefault.status, 0) << byDefault.err;
  EXPECT_NE(byDefault.out.find("character BCN_Epileptic.X (asset 0) of the project's 2 (0 BCN_Epileptic.X, 2 "
                               "Testwuson.X); --character NAME exports another"),
            std::string::npos)
      << byDefault.out;
  const nlohmann::json bcnInfo = info(bcn);
  EXPECT_EQ(bcnInfo["name"], "BCN_Epileptic");
  ASSERT_EQ(bcnInfo["levels"].size(), 3u);
  EXPECT_EQ(bcnInfo["levels"][2]["threshold"], 50.0);
  EXPECT_EQ(bcnInfo["levels"][1]["clips"].size(), 2u); // its own clip and the mapped CMU motion
  // by stem or index: the same character; said without a note
  const test::CliRun byIndex = runMotionlod({"export", file.string(), "--character", "2", "--plugin", "bundle", "-o",
                                             (dir / "index.mlodb").string(), "--json"});
  ASSERT_EQ(byIndex.status, 0) << byIndex.err;
  EXPECT_EQ(nlohmann::json::parse(byIndex.out)["character"], "Testwuson.X");
  EXPECT_EQ(nlohmann::json::parse(byIndex.out)["message"].get<std::string>().find("--character"), std::string::npos);

  // an unknown name: exit 2, nothing written, the characters listed
  const std::string none = (dir / "none.mlodb").string();
  const test::CliRun unknown =
      runMotionlod({"export", file.string(), "--character", "Wuson", "--plugin", "bundle", "-o", none});
  EXPECT_EQ(unknown.status, 2);
  EXPECT_NE(unknown.err.find("error: " + file.string() +
                             ": --character Wuson: the project has no character 'Wuson'; the project's characters: 0 "
                             "BCN_Epileptic.X, 2 Testwuson.X"),
            std::string::npos)
      << unknown.err;
  EXPECT_FALSE(fs::exists(none));
  const test::CliRun motion =
      runMotionlod({"export", file.string(), "--character", "01_01.bvh", "--plugin", "bundle", "-o", none});
  EXPECT_EQ(motion.status, 2);
  EXPECT_NE(motion.err.find("is a motion (asset 1), exported with BCN_Epileptic.X"), std::string::npos) << motion.err;
  const test::CliRun both = runMotionlod(
      {"export", file.string(), "--character", "Testwuson.X", "--asset", "0", "--plugin", "bundle", "-o", none});
  EXPECT_EQ(both.status, 2);
  EXPECT_NE(both.err.find("--character and --asset both pick"), std::string::npos) << both.err;
  const test::CliRun onAFile = runMotionlod(
      {"export", test::modelPath("X/Testwuson.X"), "--character", "Testwuson.X", "--plugin", "bundle", "-o", none});
  EXPECT_EQ(onAFile.status, 2);
  EXPECT_NE(onAFile.err.find("--character applies to a project"), std::string::npos) << onAFile.err;
  EXPECT_FALSE(fs::exists(none));

  // batch: a job's "character", good and bad
  const nlohmann::json manifest = {
      {"jobs",
       {{{"input", "two.mlod"}, {"plugin", "bundle"}, {"output", "batch_wuson.mlodb"}, {"character", "Testwuson"}},
        {{"input", "two.mlod"}, {"plugin", "bundle"}, {"output", "batch_none.mlodb"}, {"character", "Nobody.X"}}}}};
  std::ofstream(dir / "manifest.json") << manifest.dump(2);
  const test::CliRun batch = runMotionlod({"batch", (dir / "manifest.json").string(), "--json", "--jobs", "1"});
  EXPECT_EQ(batch.status, 2) << batch.err;
  const nlohmann::json report = nlohmann::json::parse(batch.out);
  ASSERT_EQ(report["jobs"].size(), 2u);
  EXPECT_TRUE(report["jobs"][0]["ok"].get<bool>());
  EXPECT_EQ(report["jobs"][0]["character"], "Testwuson.X");
  EXPECT_EQ(info((dir / "batch_wuson.mlodb").string())["levels"].size(), 2u);
  EXPECT_FALSE(report["jobs"][1]["ok"].get<bool>());
  EXPECT_NE(batch.err.find("--character Nobody.X: the project has no character 'Nobody.X'"), std::string::npos)
      << batch.err;
  EXPECT_FALSE(fs::exists(dir / "batch_none.mlodb"));
}

// The JSON chunk of a .glb.
nlohmann::json glbDocument(const fs::path& file) {
  const std::string bytes = test::readText(file.string());
  EXPECT_GE(bytes.size(), 20u);
  EXPECT_EQ(bytes.compare(0, 4, "glTF"), 0);
  std::uint32_t length = 0;
  std::memcpy(&length, bytes.data() + 12, 4);
  return nlohmann::json::parse(bytes.begin() + 20, bytes.begin() + 20 + std::ptrdiff_t(length));
}

// Issue 28, item 5: `export CHARACTER --motion CLIP` plays the clip on the character through
// the automatic mapping (the path bench-crowd --scene --motion takes), says how much of the
// character it drives, and writes the clip's animation at every level, named after its file,
// every joint keyed: the mapped ones at every frame of the original level, the others held.
TEST(CliExport, MotionPlaysOnTheCharacter) {
  const fs::path out = freshFolder("motion") / "bcn_0103.glb";
  const std::string bcn = test::modelPath("X/BCN_Epileptic.X"), clip = test::modelPath("BVH/01_03.bvh");
  const test::CliRun run = runMotionlod({"export", bcn, "--motion", clip, "--plugin", "gltf", "-o", out.string(), "-q"});
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(run.err, "");
  const std::string said = "motion " + clip + ": clip '01_03' on BCN_Epileptic, ";
  const std::size_t at = run.out.find(said);
  ASSERT_EQ(at, 0u) << run.out;
  const int mapped = std::atoi(run.out.c_str() + said.size()); // "28 joints mapped by name, driving 24 of ..."
  EXPECT_NE(run.out.find(" joints mapped by name, driving 24 of BCN_Epileptic's 33 joints with a child (73%); "
                         "the others hold their rest pose\n"),
            std::string::npos)
      << run.out;
  EXPECT_GE(mapped, 24);

  const nlohmann::json document = glbDocument(out);
  const nlohmann::json& nodes = document["nodes"];
  const std::size_t joints = document["skins"][0]["joints"].size();
  ASSERT_EQ(joints, 54u);
  int animations = 0;
  for (const nlohmann::json& animation : document["animations"]) {
    const std::string name = animation["name"];
    if (name.rfind("01_03_LOD", 0) != 0)
      continue;
    SCOPED_TRACE(name);
    ++animations;
    EXPECT_EQ(animation["extras"]["frameCount"], 4511);
    EXPECT_EQ(animation["extras"]["fps"], 120.0);
    std::map<std::string, int> keys; // joint -> rotation keys
    for (const nlohmann::json& channel : animation["channels"])
      if (channel["target"]["path"] == "rotation") {
        const nlohmann::json& sampler = animation["samplers"][channel["sampler"].get<std::size_t>()];
        keys[nodes[channel["target"]["node"].get<std::size_t>()]["name"]] =
            document["accessors"][sampler["input"].get<std::size_t>()]["count"].get<int>();
      }
    EXPECT_EQ(keys.size(), joints); // every joint keyed
    if (name != "01_03_LOD0")
      continue;
    // the original level: each mapped joint keyed at every frame, each other held by <= 2 keys
    int everyFrame = 0;
    for (const auto& [joint, count] : keys) {
      everyFrame += count == 4511;
      EXPECT_TRUE(count == 4511 || count <= 2) << joint << ": " << count;
    }
    EXPECT_EQ(everyFrame, mapped);
    // the checked table of CMU subject 01 on BCN_Epileptic agrees on most joints
    const nlohmann::json table = nlohmann::json::parse(
        test::readText(std::string(MLOD_TEST_DATA_DIR) + "/mappings/cmu_01_01_to_bcn_epileptic.json"));
    int agreed = 0;
    for (const nlohmann::json& pair : table["pairs"])
      agreed += keys[pair["character"].get<std::string>()] == 4511;
    EXPECT_GE(agreed, 24) << "of " << table["pairs"].size();
  }
  EXPECT_EQ(animations, 4);
  // the project's importer reads the clip back at its frames
  const test::CliRun info = runMotionlod({"info", out.string(), "--json"});
  ASSERT_EQ(info.status, 0) << info.err;
  int found = 0;
  const nlohmann::json back = nlohmann::json::parse(info.out);
  for (const nlohmann::json& c : back["clips"])
    if (c["name"].get<std::string>().rfind("01_03_LOD", 0) == 0) {
      ++found;
      EXPECT_EQ(c["frames"], 4511);
    }
  EXPECT_EQ(found, 4);
}

// A motion that hardly fits the character is refused with the figures unless --allow-partial;
// --motion is for a file, not a project.
TEST(CliExport, MotionOfAnotherRigIsRefusedUnlessPartialIsAllowed) {
  const fs::path dir = freshFolder("partial");
  const std::string wuson = test::modelPath("X/Testwuson.X"), clip = test::modelPath("BVH/01_03.bvh");
  const fs::path out = dir / "wuson.glb";
  test::CliRun run = runMotionlod({"export", wuson, "--motion", clip, "--plugin", "gltf", "-o", out.string(), "-q"});
  EXPECT_EQ(run.status, 2);
  EXPECT_EQ(run.err, "error: " + clip + ": the automatic mapping drives 7 of Testwuson's 30 joints with a child (23%), "
                                        "below 50%: the rest of the body would hold its rest pose (--allow-partial "
                                        "exports it anyway)\n");
  EXPECT_FALSE(fs::exists(out));
  run = runMotionlod({"export", wuson, "--motion", clip, "--allow-partial", "--mesh-ratio", "0.5", "--plugin", "gltf",
                      "-o", out.string(), "-q"});
  EXPECT_EQ(run.status, 0) << run.err;
  EXPECT_NE(run.out.find("driving 7 of Testwuson's 30 joints with a child (23%)"), std::string::npos) << run.out;
  EXPECT_TRUE(fs::exists(out));
  const fs::path project = dir / "p.mlod";
  std::ofstream(project) << "{}";
  run = runMotionlod({"export", project.string(), "--motion", clip, "--plugin", "gltf", "-o", (dir / "p.glb").string()});
  EXPECT_EQ(run.status, 2);
  EXPECT_NE(run.err.find("--motion applies to a file"), std::string::npos) << run.err;
}

} // namespace
} // namespace mlod
