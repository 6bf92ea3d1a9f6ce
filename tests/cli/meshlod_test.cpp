// The command-line contract of `motionlod meshlod FILE --ratio R[,R…] [--json]`: the JSON
// keys exactly (issue 5's, and issue 14's "error_cm" per level), the counts reached, the
// warning where a mesh cannot be simplified that far, and `error: FILE: reason` with exit 2
// for bad input.

#include "cli_runner.h"
#include "test_files.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <cmath>
#include <unistd.h>

namespace mlod {
namespace {

using test::keysOf;
using test::runMotionlod;

// Guards the JSON document: the keys, one level per ratio in order, each within 5% of its
// triangle count (BCN_Epileptic stopped at 52% for every ratio before issue 14), errors in cm
// (max_error the largest of bind and animated_max, animated_mean <= animated_max), warning null.
TEST(CliMeshLod, JsonKeysAndValues) {
  const test::CliRun run = runMotionlod(
      {"meshlod", test::modelPath("X/BCN_Epileptic.X"), "--unit-scale", "100", "--ratio", "0.5,0.25,0.1", "--json"});
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json doc = nlohmann::json::parse(run.out);
  EXPECT_EQ(keysOf(doc), (std::vector<std::string>{"file", "levels", "locked_vertices", "triangles", "vertices"}));
  EXPECT_EQ(doc["triangles"], 5126);
  EXPECT_EQ(doc["vertices"], 3014);
  EXPECT_EQ(doc["locked_vertices"], 0) << "BCN_Epileptic is manifold";
  ASSERT_EQ(doc["levels"].size(), 3u);
  const double ratios[] = {0.5, 0.25, 0.1};
  for (std::size_t i = 0; i < 3; ++i) {
    const nlohmann::json& level = doc["levels"][i];
    EXPECT_EQ(keysOf(level),
              (std::vector<std::string>{"error_cm", "max_error", "ratio", "seconds", "shared_vertices_preserved",
                                        "triangles", "vertices", "warning"}));
    EXPECT_EQ(keysOf(level["error_cm"]), (std::vector<std::string>{"animated_max", "animated_mean", "bind"}));
    EXPECT_EQ(level["ratio"], ratios[i]);
    EXPECT_NEAR(level["triangles"].get<double>(), ratios[i] * 5126, 0.05 * ratios[i] * 5126);
    EXPECT_TRUE(level["shared_vertices_preserved"].get<bool>());
    EXPECT_TRUE(level["warning"].is_null());
    const nlohmann::json& error = level["error_cm"];
    EXPECT_GT(error["bind"].get<double>(), 0.0);
    EXPECT_GT(error["animated_max"].get<double>(), 0.0);
    EXPECT_LE(error["animated_mean"].get<double>(), error["animated_max"].get<double>());
    EXPECT_EQ(level["max_error"].get<double>(),
              std::max(error["bind"].get<double>(), error["animated_max"].get<double>()));
    EXPECT_LT(level["max_error"].get<double>(), 20.0) << "cm, on a 1.9 m character";
    EXPECT_GT(level["seconds"].get<double>(), 0.0);
  }
}

// Guards the warning: one closed cube cannot go below two triangles (and, being the only
// component, is never pruned), so 10% of its 12 triangles warns with the count reached.
TEST(CliMeshLod, ARatioOutOfReachWarns) {
  const test::CliRun run =
      runMotionlod({"meshlod", test::modelPath("X/test_cube_text.x"), "--ratio", "0.5,0.1", "--json"});
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json doc = nlohmann::json::parse(run.out);
  ASSERT_EQ(doc["levels"].size(), 2u);
  EXPECT_TRUE(doc["levels"][0]["warning"].is_null());
  const nlohmann::json& far = doc["levels"][1];
  ASSERT_TRUE(far["warning"].is_string());
  EXPECT_NE(far["warning"].get<std::string>().find(std::to_string(far["triangles"].get<int>())), std::string::npos);
}

// Guards component pruning: 64 separate closed cubes stopped at 16.7% when 10% was asked;
// whole cubes now go when that is the cheapest step, so 10% is reached without a warning.
TEST(CliMeshLod, SmallComponentsArePrunedToReachTenPercent) {
  const test::CliRun run =
      runMotionlod({"meshlod", test::modelPath("Collada/anims_with_full_rotations_between_keys.DAE"), "--ratio",
                    "0.5,0.25,0.1", "--json"});
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json doc = nlohmann::json::parse(run.out);
  ASSERT_EQ(doc["triangles"], 768);
  ASSERT_EQ(doc["levels"].size(), 3u);
  for (const nlohmann::json& level : doc["levels"]) {
    const double target = level["ratio"].get<double>() * 768;
    EXPECT_NEAR(level["triangles"].get<double>(), target, 0.05 * target);
    EXPECT_TRUE(level["warning"].is_null()) << level["warning"];
  }
}

// Guards the readable table: bind and animated errors, no warning where the ratio is reached.
TEST(CliMeshLod, Table) {
  const test::CliRun run =
      runMotionlod({"meshlod", test::modelPath("X/BCN_Epileptic.X"), "--unit-scale", "m", "--ratio", "0.5"});
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_NE(run.out.find("max error cm"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("anim max cm"), std::string::npos) << run.out;
  EXPECT_EQ(run.out.find("warning:"), std::string::npos) << run.out;
}

// Guards the error contract: exit 2 and `error: FILE: reason` for bad ratios, a file
// without a mesh and a missing file; nothing on stdout.
TEST(CliMeshLod, BadInputIsExitTwo) {
  const std::string bcn = test::modelPath("X/BCN_Epileptic.X");
  for (const std::vector<std::string>& arguments :
       {std::vector<std::string>{"meshlod", bcn, "--ratio", "0"},
        std::vector<std::string>{"meshlod", bcn, "--ratio", "1.5"},
        std::vector<std::string>{"meshlod", bcn, "--ratio", "0.5,abc"},
        std::vector<std::string>{"meshlod", bcn, "--ratio", "nan"},
        std::vector<std::string>{"meshlod", test::modelPath("BVH/01_01.bvh"), "--ratio", "0.5"},
        std::vector<std::string>{"meshlod", "/nonexistent/file.x", "--ratio", "0.5"}}) {
    const test::CliRun run = runMotionlod(arguments);
    EXPECT_EQ(run.status, 2) << arguments[1] << " " << arguments[3];
    EXPECT_EQ(run.err.rfind("error: " + arguments[1] + ": ", 0), 0u) << run.err;
    EXPECT_TRUE(run.out.empty()) << run.out;
  }
  EXPECT_EQ(runMotionlod({"meshlod", bcn}).status, 2) << "--ratio is required";
}

// Guards `export --mesh-ratio`: LOD0 plus one level per ratio; a bad ratio or a project is
// exit 2 with nothing written.
TEST(CliMeshLod, ExportWithMeshRatios) {
  namespace fs = std::filesystem;
  const fs::path out = test::freshFolder("meshlod", "ratios") / "out.mlodb";
  const std::string bcn = test::modelPath("X/BCN_Epileptic.X");
  test::CliRun run =
      runMotionlod({"export", bcn, "--plugin", "bundle", "-o", out.string(), "--mesh-ratio", "0.5,0.25,0.1", "--json"});
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json doc = nlohmann::json::parse(run.out);
  EXPECT_EQ(doc["levels"], 4);
  // The bundle read back (info reads it as an engine does): LOD0 the whole mesh, then one
  // level per ratio, each at most round(ratio x triangles) and within 5% of it (the
  // simplifier's promise, MeshLodBcn.RatiosReachTheirTriangleCountsWithinFivePercent).
  const test::CliRun info = runMotionlod({"info", out.string(), "--json"});
  ASSERT_EQ(info.status, 0) << info.err;
  const nlohmann::json bundle = nlohmann::json::parse(info.out);
  const test::CliRun source = runMotionlod({"info", bcn, "--json"});
  ASSERT_EQ(source.status, 0) << source.err;
  const int triangles = nlohmann::json::parse(source.out)["meshes"][0]["triangles"].get<int>();
  ASSERT_EQ(bundle["levels"].size(), 4u);
  ASSERT_TRUE(bundle["levels"][0]["mesh"].is_object());
  EXPECT_EQ(bundle["levels"][0]["mesh"]["triangles"].get<int>(), triangles);
  const double ratios[] = {0.5, 0.25, 0.1};
  for (std::size_t l = 1; l < 4; ++l) {
    SCOPED_TRACE("LOD" + std::to_string(l));
    const nlohmann::json& level = bundle["levels"][l];
    ASSERT_TRUE(level["mesh"].is_object());
    EXPECT_DOUBLE_EQ(level["mesh_ratio"].get<double>(), ratios[l - 1]);
    const double target = double(std::llround(ratios[l - 1] * triangles));
    const double got = level["mesh"]["triangles"].get<double>();
    EXPECT_LE(got, target);
    EXPECT_GE(got, 0.95 * target);
  }
  fs::remove(out);
  for (const char* bad : {"0", "1.5", "x", "0.5,nan"}) {
    run = runMotionlod({"export", bcn, "--plugin", "bundle", "-o", out.string(), "--mesh-ratio", bad});
    EXPECT_EQ(run.status, 2) << bad;
    EXPECT_EQ(run.err.rfind("error: " + bcn + ": ", 0), 0u) << run.err;
    EXPECT_FALSE(fs::exists(out));
  }
}

// Guards issue 28, item 2: levels by --mesh-ratio have no switch distance, so the glTF has
// MSFT_lod without MSFT_screencoverage (it carried [1, 1, 1, 0]) and stderr says why; the
// summary on stdout stays as it was.
TEST(CliMeshLod, GltfExportWithMeshRatiosWarnsOfNoCoverage) {
  namespace fs = std::filesystem;
  const fs::path out = test::freshFolder("meshlod", "gltf") / "out.gltf";
  const std::string bcn = test::modelPath("X/BCN_Epileptic.X");
  const test::CliRun run =
      runMotionlod({"export", bcn, "--plugin", "gltf", "-o", out.string(), "--mesh-ratio", "0.5,0.25,0.1", "--quiet"});
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(run.err, "warning: " + out.string() +
                         ": no MSFT_screencoverage: the LOD set has no bounding radius (a reader that switches by "
                         "coverage cannot tell when to show each level)\n");
  EXPECT_EQ(run.out.find("warning"), std::string::npos) << run.out;
  std::ifstream file(out);
  const nlohmann::json document = nlohmann::json::parse(file);
  int lods = 0;
  for (const nlohmann::json& node : document["nodes"]) {
    if (!node.contains("extensions"))
      continue;
    ++lods;
    EXPECT_EQ(node["extensions"]["MSFT_lod"]["ids"].size(), 3u);
    EXPECT_FALSE(node.contains("extras") && node["extras"].contains("MSFT_screencoverage")) << node.dump();
  }
  EXPECT_EQ(lods, 1);
}

} // namespace
} // namespace mlod
