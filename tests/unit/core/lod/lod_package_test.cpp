// LodPackage (core/lod/lod_package.h): what exporters get, computed once by core.

#include "core/lod/lod_package.h"
#include "io/importer.h"

#include <gtest/gtest.h>

#include <string>

namespace mlod {
namespace {

Asset importOrSkip(const std::string& path, double unitScale) {
  ImportOptions options;
  options.unitScale = unitScale;
  Result<Asset> asset = importAsset(path, options);
  if (!asset)
    ADD_FAILURE() << path << ": " << asset.message();
  return asset ? std::move(asset).value() : Asset{};
}

TEST(LodPackage, SampleHasEveryLevelWithRuntimeClipsAndMetrics) {
  const Asset asset = importOrSkip(MLOD_SAMPLE, 2.54 / 0.45);
  int calls = 0;
  double last = -1.0;
  Result<LodPackage> package = buildLodPackage(asset, {}, [&](double fraction, std::string_view) {
    EXPECT_GE(fraction, last);
    last = fraction;
    ++calls;
    return true;
  });
  ASSERT_TRUE(package) << package.message();
  EXPECT_EQ(package->lods.levels.size(), 4u); // the default LOD set: 1 pixel, 4 levels
  ASSERT_EQ(package->levels.size(), 4u);
  EXPECT_EQ(package->name, "cmu_01_01_excerpt");
  EXPECT_FALSE(package->mesh);
  EXPECT_GT(calls, 4);
  EXPECT_DOUBLE_EQ(last, 1.0);
  for (std::size_t i = 0; i < package->levels.size(); ++i) {
    const LodPackageLevel& level = package->levels[i];
    EXPECT_EQ(level.index, int(i));
    ASSERT_EQ(level.runtimeClips.size(), asset.clips.size());
    ASSERT_EQ(level.metrics.size(), asset.clips.size());
    EXPECT_EQ(level.runtimeClips[0].jointCount(), level.skeleton().jointCount());
    EXPECT_EQ(level.runtimeClips[0].frameCount(), asset.clips[0].frameCount);
    EXPECT_EQ(int(level.inverseBinds.size()), level.skeleton().jointCount());
    EXPECT_EQ(level.skeleton().jointCount(), level.settings.activeJoints);
    // the metrics' clusters are the ones the level was built with
    EXPECT_EQ(level.metrics[0].clusters.joints, level.build.motion.clusters[0].joints);
    EXPECT_EQ(level.metrics[0].clusterCount, level.build.motion.clusters[0].clusterCount());
  }
  // coarser levels cluster more
  EXPECT_EQ(package->levels[0].metrics[0].threshold, 0.0);
  EXPECT_GT(package->levels[3].metrics[0].simplifiedPercent, package->levels[1].metrics[0].simplifiedPercent);
}

TEST(LodPackage, LevelsAreSelectedAndCheckedAndCancelStops) {
  const Asset asset = importOrSkip(MLOD_SAMPLE, 2.54 / 0.45);
  const int pick[] = {2, 0};
  Result<LodPackage> picked = buildLodPackage(asset, pick);
  ASSERT_TRUE(picked) << picked.message();
  ASSERT_EQ(picked->levels.size(), 2u);
  EXPECT_EQ(picked->levels[0].index, 2);
  EXPECT_EQ(picked->levels[1].index, 0);

  const int bad[] = {7};
  Result<LodPackage> outOfRange = buildLodPackage(asset, bad);
  ASSERT_FALSE(outOfRange);
  EXPECT_NE(outOfRange.message().find("level 7 does not exist"), std::string::npos) << outOfRange.message();
  const int twice[] = {1, 1};
  EXPECT_FALSE(buildLodPackage(asset, twice));

  int calls = 0;
  Result<LodPackage> cancelled = buildLodPackage(asset, {}, [&](double, std::string_view) { return ++calls < 3; });
  ASSERT_FALSE(cancelled);
  EXPECT_EQ(cancelled.message(), kLodPackageCancelled);
  EXPECT_EQ(calls, 3);
}

TEST(LodPackage, SkinnedCharacterCarriesLevelMeshes) {
  const Asset asset = importOrSkip(std::string(MLOD_ASSIMP_MODELS) + "/X/BCN_Epileptic.X", 100.0);
  Result<LodPackage> package = buildLodPackage(asset);
  ASSERT_TRUE(package) << package.message();
  ASSERT_TRUE(package->mesh);
  for (const LodPackageLevel& level : package->levels) {
    ASSERT_NE(level.mesh(), nullptr);
    EXPECT_FALSE(level.mesh()->validate(level.skeleton().jointCount()));
    EXPECT_EQ(int(level.mesh()->triangleCount()), level.settings.triangles);
    std::optional<SkinnedMesh> full = levelMeshOnFullSkeleton(level);
    ASSERT_TRUE(full);
    EXPECT_FALSE(full->validate(package->skeleton.jointCount()));
  }
  const SkinnedMesh* coarsest = package->levels.back().mesh();
  const SkinnedMesh* finest = package->levels.front().mesh();
  ASSERT_TRUE(coarsest && finest);
  EXPECT_LT(coarsest->triangleCount(), finest->triangleCount());
}

} // namespace
} // namespace mlod
