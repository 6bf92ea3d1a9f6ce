// The command-line contract of DESIGN.md section 6 for `simplify`: the JSON keys exactly,
// the defaults, the readable table, and `error: FILE: reason` with exit 2 for bad input.

#include "cli_runner.h"
#include "test_files.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace mlod {
namespace {

using test::runMotionlod;

std::vector<std::string> keysOf(const nlohmann::json& object) {
  std::vector<std::string> keys;
  for (const auto& item : object.items())
    keys.push_back(item.key());
  return keys;
}

// Guards the JSON document: keys exactly as DESIGN.md lists them, one entry per threshold,
// the defaults (greedy, alpha 5), the CMU clip's figures.
TEST(CliSimplify, JsonKeysAndValues) {
  const test::CliRun run = runMotionlod(
      {"simplify", test::modelPath("BVH/01_01.bvh"), "--threshold", "5,300", "--unit-scale", "cmu", "--json"});
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json doc = nlohmann::json::parse(run.out);
  EXPECT_EQ(keysOf(doc), (std::vector<std::string>{"alpha", "clip", "file", "fps", "frames", "mode", "seconds",
                                                   "thresholds", "unit_scale"}));
  EXPECT_EQ(doc["frames"], 2752);
  EXPECT_EQ(doc["fps"], 120.0);
  EXPECT_EQ(doc["mode"], "greedy");
  EXPECT_EQ(doc["alpha"], 5.0);
  EXPECT_NEAR(doc["unit_scale"].get<double>(), 5.6444, 1e-3);
  ASSERT_EQ(doc["thresholds"].size(), 2u);
  const nlohmann::json& level = doc["thresholds"][1];
  EXPECT_EQ(keysOf(level),
            (std::vector<std::string>{"clusters", "joints", "max_error", "max_joint_position_error_cm",
                                      "mean_joint_position_error_cm", "simplified_joint_percent", "threshold"}));
  EXPECT_EQ(level["threshold"], 300.0);
  EXPECT_LE(level["max_error"].get<double>(), 300.0);
  EXPECT_GT(level["simplified_joint_percent"].get<double>(),
            doc["thresholds"][0]["simplified_joint_percent"].get<double>());
  EXPECT_EQ(level["joints"].size(), 31u); // the joints with a rotation channel
  EXPECT_EQ(keysOf(level["joints"][0]),
            (std::vector<std::string>{"clusters", "max_error", "name", "simplified_percent"}));
  EXPECT_EQ(level["joints"][0]["name"], "Hips");
}

// Guards --mode optimal, --alpha, --joint NAME=E and --clip by index.
TEST(CliSimplify, OptionsReachTheAlgorithm) {
  const std::string file = test::modelPath("BVH/01_01.bvh");
  const auto percent = [&](std::vector<std::string> extra, const char* joint = nullptr) {
    std::vector<std::string> arguments{"simplify", file, "--threshold", "50", "--unit-scale", "cmu", "--json"};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    const test::CliRun run = runMotionlod(arguments);
    EXPECT_EQ(run.status, 0) << run.err;
    const nlohmann::json doc = nlohmann::json::parse(run.out);
    if (!joint)
      return doc["thresholds"][0]["simplified_joint_percent"].get<double>();
    for (const nlohmann::json& j : doc["thresholds"][0]["joints"])
      if (j["name"] == joint)
        return j["simplified_percent"].get<double>();
    ADD_FAILURE() << joint;
    return -1.0;
  };
  const double greedy = percent({});
  EXPECT_GE(percent({"--mode", "optimal"}), greedy);
  EXPECT_GT(percent({"--alpha", "0"}), greedy);
  EXPECT_LT(percent({"--joint", "Head=0"}, "Head"), percent({}, "Head"));
  EXPECT_EQ(percent({"--clip", "0"}), greedy);
}

// Guards the readable output: a Table 1 layout with an Original column and the figures.
TEST(CliSimplify, TableLikeThePaper) {
  const test::CliRun run =
      runMotionlod({"simplify", test::modelPath("BVH/01_01.bvh"), "--threshold", "5,50", "--unit-scale", "cmu"});
  ASSERT_EQ(run.status, 0) << run.err;
  for (const char* text : {"Original", "E=5", "E=50", "clusters", "max joint position error (cm)", "LHipJoint"})
    EXPECT_NE(run.out.find(text), std::string::npos) << text << "\n" << run.out;
}

// Guards the error contract for every kind of bad argument and file.
TEST(CliSimplify, BadInputExitsTwoWithMessage) {
  const std::string file = test::modelPath("BVH/01_01.bvh");
  const struct {
    std::vector<std::string> arguments;
    const char* reason;
  } cases[] = {
      {{"simplify", file, "--threshold", "-5"}, "--threshold is -5"},
      {{"simplify", file, "--threshold", "nan"}, "NaN"},
      {{"simplify", file, "--threshold", "5,-1"}, "--threshold entry 2 is -1"},
      {{"simplify", file, "--threshold", "5,x"}, "'x' is not a number"},
      {{"simplify", file, "--threshold", "5", "--alpha", "five"}, "--alpha is 'five'"},
      {{"simplify", file, "--threshold", "5", "--alpha", "-1"}, "--alpha"},
      {{"simplify", file, "--threshold", "5", "--mode", "best"}, "--mode 'best'"},
      {{"simplify", file, "--threshold", "5", "--joint", "NoSuchJoint=5"}, "no joint is named 'NoSuchJoint'"},
      {{"simplify", file, "--threshold", "5", "--joint", "Head"}, "NAME=E"},
      {{"simplify", file, "--threshold", "5", "--clip", "7"}, "no clip '7'"},
      {{"simplify", "/no/such/file.bvh", "--threshold", "5"}, ""},
      {{"simplify", "/no/such/project.mlod", "--threshold", "5"}, ".mlod projects are not supported yet"},
  };
  for (const auto& c : cases) {
    const test::CliRun run = runMotionlod(c.arguments);
    SCOPED_TRACE(c.arguments.back());
    EXPECT_EQ(run.status, 2);
    EXPECT_EQ(run.err.rfind("error: " + c.arguments[1] + ": ", 0), 0u) << run.err;
    EXPECT_NE(run.err.find(c.reason), std::string::npos) << run.err;
    EXPECT_TRUE(run.out.empty()) << run.out;
  }
  const test::CliRun missing = runMotionlod({"simplify", file});
  EXPECT_EQ(missing.status, 2); // --threshold is required
}

} // namespace
} // namespace mlod
