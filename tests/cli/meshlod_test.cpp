// The command-line contract of `motionlod meshlod FILE --ratio R[,R…] [--json]` (issue 5):
// the JSON keys exactly, the warning where the locks stop short of a ratio, and
// `error: FILE: reason` with exit 2 for bad input.

#include "cli_runner.h"
#include "test_files.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace mlod {
namespace {

using test::keysOf;
using test::runMotionlod;

// Guards the JSON document: the keys, one level per ratio in order, counts falling
// with the ratio, max_error in cm, warning null where the ratio is reached.
TEST(CliMeshLod, JsonKeysAndValues) {
  const test::CliRun run = runMotionlod(
      {"meshlod", test::modelPath("X/BCN_Epileptic.X"), "--unit-scale", "100", "--ratio", "0.9,0.75,0.5", "--json"});
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json doc = nlohmann::json::parse(run.out);
  EXPECT_EQ(keysOf(doc), (std::vector<std::string>{"file", "levels", "locked_vertices", "triangles", "vertices"}));
  EXPECT_EQ(doc["triangles"], 5126);
  EXPECT_EQ(doc["vertices"], 3014);
  EXPECT_GT(doc["locked_vertices"].get<int>(), 1341); // the shared vertices and then some
  ASSERT_EQ(doc["levels"].size(), 3u);
  int previous = 5126;
  for (std::size_t i = 0; i < 3; ++i) {
    const nlohmann::json& level = doc["levels"][i];
    EXPECT_EQ(keysOf(level), (std::vector<std::string>{"max_error", "ratio", "seconds", "shared_vertices_preserved",
                                                       "triangles", "vertices", "warning"}));
    EXPECT_LT(level["triangles"].get<int>(), previous);
    previous = level["triangles"].get<int>();
    EXPECT_TRUE(level["shared_vertices_preserved"].get<bool>());
    EXPECT_GT(level["max_error"].get<double>(), 0.0);
    EXPECT_LT(level["max_error"].get<double>(), 20.0) << "cm, on a 1.8 m character";
    EXPECT_GT(level["seconds"].get<double>(), 0.0);
  }
  EXPECT_EQ(doc["levels"][0]["ratio"], 0.9);
  EXPECT_TRUE(doc["levels"][0]["warning"].is_null());
  EXPECT_NEAR(doc["levels"][0]["triangles"].get<int>(), 0.9 * 5126, 0.1 * 0.9 * 5126);
  // 44% of BCN_Epileptic's vertices blend joints: half its triangles is out of reach
  EXPECT_TRUE(doc["levels"][2]["warning"].is_string());
  EXPECT_NE(doc["levels"][2]["warning"].get<std::string>().find(std::to_string(doc["levels"][2]["triangles"].get<int>())),
            std::string::npos);
}

// Guards the readable table and its warning line.
TEST(CliMeshLod, TableAndWarning) {
  const test::CliRun run =
      runMotionlod({"meshlod", test::modelPath("X/BCN_Epileptic.X"), "--unit-scale", "m", "--ratio", "0.5"});
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_NE(run.out.find("max error cm"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("warning:"), std::string::npos) << run.out;
}

// Guards the error contract: exit 2 and `error: FILE: reason` for bad ratios, a file
// without a mesh and a missing file; nothing on stdout.
TEST(CliMeshLod, BadInputIsExitTwo) {
  const std::string bcn = test::modelPath("X/BCN_Epileptic.X");
  for (const std::vector<std::string>& arguments :
       {std::vector<std::string>{"meshlod", bcn, "--ratio", "0"}, std::vector<std::string>{"meshlod", bcn, "--ratio", "1.5"},
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

} // namespace
} // namespace mlod
