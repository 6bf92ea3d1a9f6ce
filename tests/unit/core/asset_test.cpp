#include "core/asset.h"
#include "fixtures.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace mlod {
namespace {

Asset smallAsset() {
  Asset asset;
  asset.sourcePath = "/tmp/walk.bvh";
  asset.format = "BVH";
  asset.skeleton = test::makeChain(3);
  asset.clips.push_back(Clip::restPose(asset.skeleton, 10, 30.0));
  asset.clips.back().name = "walk";
  return asset;
}

// Guards Asset::validate(): each broken rule in turn.
TEST(Asset, ValidateRejectsEachRule) {
  EXPECT_FALSE(smallAsset().validate());
  Asset a = smallAsset();
  a.unitScale = 0.0;
  EXPECT_TRUE(a.validate());
  a = smallAsset();
  a.skeleton.joints.clear();
  EXPECT_NE(a.validate().message().find("neither a skeleton nor a mesh"), std::string::npos);
  a = smallAsset();
  a.clips.back().jointCount = 2;
  EXPECT_TRUE(a.validate());
  Asset meshOnly;
  EXPECT_TRUE(meshOnly.validate());
}

// Guards the `info --json` document: the keys tools read.
TEST(Asset, DescribeJsonHasTheCounts) {
  const nlohmann::json doc = nlohmann::json::parse(describeAssetJson(smallAsset()));
  EXPECT_EQ(doc["format"], "BVH");
  ASSERT_EQ(doc["joints"].size(), 3u);
  EXPECT_TRUE(doc["joints"][0]["parent"].is_null());
  EXPECT_EQ(doc["joints"][2]["parent"], "j1");
  EXPECT_EQ(doc["clips"][0]["frames"], 10);
  EXPECT_EQ(doc["clips"][0]["fps"], 30.0);
  EXPECT_EQ(doc["meshes"].size(), 0u);
}

} // namespace
} // namespace mlod
