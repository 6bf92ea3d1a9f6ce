// Every kind of bad file gives an Error with a message that names the problem, and
// never a crash or a hang. Each test writes its own broken file.

#include "io/importer.h"
#include "test_files.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <random>

namespace mlod {
namespace {

const char* kRoot6 = "Xposition Yposition Zposition Zrotation Yrotation Xrotation";
const char* kZyx = "Zrotation Yrotation Xrotation";

void expectRefused(const std::string& path, const std::string& fragment = {}) {
  const Result<Asset> asset = importAsset(path);
  ASSERT_FALSE(asset.ok()) << path << " was accepted";
  EXPECT_FALSE(asset.message().empty());
  if (!fragment.empty()) {
    EXPECT_NE(asset.message().find(fragment), std::string::npos) << "message: " << asset.message();
  }
}

// Guards the empty file.
TEST(BadInput, EmptyFile) { expectRefused(test::writeTemp("empty.bvh", ""), "empty"); }

// Guards a path that does not exist, and a directory given as a file.
TEST(BadInput, MissingFileAndDirectory) {
  expectRefused("/nonexistent/walk.bvh", "no such file");
  expectRefused(std::filesystem::temp_directory_path().string(), "directory");
}

// Guards a file cut off inside the hierarchy.
TEST(BadInput, TruncatedHierarchy) {
  const std::string full = test::makeBvh(kRoot6, kZyx, 1, "0.01", "0 0 0 0 0 0 0 0 0\n");
  expectRefused(test::writeTemp("cut_hierarchy.bvh", full.substr(0, full.find("End Site"))));
}

// Guards a file cut off inside the motion data (in the middle of a row).
TEST(BadInput, TruncatedMotion) {
  expectRefused(test::writeTemp("cut_motion.bvh",
                                test::makeBvh(kRoot6, kZyx, 2, "0.01", "0 0 0 0 0 0 0 0 0\n1 2 3 4")));
}

// Guards a header whose frame count is larger than the data.
TEST(BadInput, FrameCountLargerThanData) {
  expectRefused(test::writeTemp("lying.bvh", test::makeBvh(kRoot6, kZyx, 100, "0.01",
                                                           "0 0 0 0 0 0 0 0 0\n0 0 0 0 0 0 0 0 0\n")));
}

// Guards NaN, infinite and overflowing keys: named with the joint and frame.
TEST(BadInput, NonFiniteKeys) {
  for (const char* value : {"nan", "inf", "-inf", "1e39"}) {
    SCOPED_TRACE(value);
    const std::string rows = "0 0 0 0 0 0 0 0 0\n0 0 0 0 0 0 " + std::string(value) + " 0 0\n";
    expectRefused(test::writeTemp("nan.bvh", test::makeBvh(kRoot6, kZyx, 2, "0.01", rows)), "non-finite");
  }
  const std::string rows = "0 nan 0 0 0 0 0 0 0\n";
  expectRefused(test::writeTemp("nan_root.bvh", test::makeBvh(kRoot6, kZyx, 1, "0.01", rows)), "frame 0");
}

// Guards a glTF whose node graph is cyclic (a -> b -> a, and a longer loop).
TEST(BadInput, CyclicGltf) {
  expectRefused(test::writeTemp("cycle.gltf", R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],
    "nodes":[{"name":"a","children":[1]},{"name":"b","children":[0]}]})"),
                "recursive");
  expectRefused(test::writeTemp("cycle3.gltf", R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],
    "nodes":[{"name":"a","children":[1]},{"name":"b","children":[2]},{"name":"c","children":[1]}]})"),
                "recursive");
}

// Guards a glTF whose node graph is dangling (a child index past the end).
TEST(BadInput, DanglingGltf) {
  expectRefused(test::writeTemp("dangling.gltf", R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],
    "nodes":[{"name":"a","children":[1,7]},{"name":"b"}]})"),
                "out of bounds");
}

// Guards a scene that holds nothing we can use (a glTF with one empty node).
TEST(BadInput, NothingUsable) {
  expectRefused(test::writeTemp("nothing.gltf", R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],
    "nodes":[{"name":"a"}]})"),
                "no animation and no triangle mesh");
}

class Garbage : public ::testing::TestWithParam<const char*> {};

// Guards binary garbage under every extension users bring (fixed seeds: repeatable).
TEST_P(Garbage, IsRefused) {
  for (unsigned seed = 1; seed <= 4; ++seed) {
    std::mt19937 rng(seed);
    std::string bytes(4096, '\0');
    for (char& c : bytes)
      c = static_cast<char>(rng());
    expectRefused(test::writeTemp(std::string("garbage.") + GetParam(), bytes));
  }
}

INSTANTIATE_TEST_SUITE_P(Extensions, Garbage,
                         ::testing::Values("bvh", "gltf", "glb", "fbx", "dae", "x", "obj", "smd", "md5mesh", "ply",
                                           "3ds", "blend", "ms3d", "b3d", "stl", "ase", "lwo", "noext"));

} // namespace
} // namespace mlod
