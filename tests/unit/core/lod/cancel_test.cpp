// The one cancel flag (core/cancel.h, issue 29): a flag set before the work starts stops
// every long step at its first look, with the step's own cancelled result and without the
// work; a flag set during the work stops it at the next look.

#include "core/cancel.h"
#include "core/jpc/jpc.h"
#include "core/lod/bone_reduction.h"
#include "core/lod/lod_character.h"
#include "core/lod/lod_package.h"
#include "core/lod/lod_set.h"
#include "core/mesh/mesh_lod.h"
#include "core/mesh/progressive_mesh.h"
#include "unit/core/mesh_lod_fixtures.h"

#include <atomic>
#include <gtest/gtest.h>

namespace mlod {
namespace {

// The bent tube of the mesh LOD tests, with the clip that bends it.
struct BentTube {
  test::Tube tube = test::makeTube(41, 16, 1.0f, 1.0f);
  std::vector<Clip> clips{test::tubeBendClip(tube.skeleton, 12)};
};

// The bent tube as an imported asset: its skeleton, skinned mesh and clips.
Asset bentAsset() {
  const BentTube bent;
  Asset asset;
  asset.skeleton = bent.tube.skeleton;
  asset.meshes = {bent.tube.mesh};
  asset.clips = bent.clips;
  return asset;
}

// Guards the collapse loop: a set flag leaves the order empty where the same build without it
// collapses the tube (so the flag, not the mesh, stopped it).
TEST(Cancel, PresetFlagStopsTheProgressiveMeshBeforeAnyCollapse) {
  const BentTube bent;
  const std::vector<std::vector<glm::vec3>> poses{bent.tube.mesh.positions};
  ASSERT_GT(ProgressiveMesh::build(bent.tube.mesh, poses).collapseCount(), 0u);
  const std::atomic<bool> cancel{true};
  EXPECT_EQ(ProgressiveMesh::build(bent.tube.mesh, poses, {}, {}, &cancel).collapseCount(), 0u);
}

TEST(Cancel, PresetFlagMakesMeshLodBuildReturnCancelled) {
  const BentTube bent;
  const std::atomic<bool> cancel{true};
  MeshLodSettings settings;
  settings.cancel = &cancel;
  Result<MeshLod> lod = MeshLod::build(bent.tube.mesh, &bent.tube.skeleton, bent.clips, settings);
  ASSERT_FALSE(lod);
  EXPECT_EQ(lod.message(), kCancelled);
  settings.cancel = nullptr; // the same build without the flag succeeds
  EXPECT_TRUE(MeshLod::build(bent.tube.mesh, &bent.tube.skeleton, bent.clips, settings));
}

// A null flag is never cancelled; a clear one is not either.
TEST(Cancel, NullOrClearFlagIsNotCancelled) {
  EXPECT_FALSE(cancelled(nullptr));
  std::atomic<bool> flag{false};
  EXPECT_FALSE(cancelled(&flag));
  flag = true;
  EXPECT_TRUE(cancelled(&flag));
}

// Guards JPC's per-joint loop: with the flag set no joint is clustered, although the same
// call without it clusters some.
TEST(Cancel, PresetFlagLeavesEveryJointOfJpcUnclustered) {
  const BentTube bent;
  Result<JpcClip> prepared = JpcClip::prepare(bent.tube.skeleton, bent.clips[0], {});
  ASSERT_TRUE(prepared) << prepared.message();
  const double threshold = 1000.0;
  int clustered = 0;
  for (const JointClustering& joint : prepared->cluster(0, threshold))
    clustered += joint.clusteredFrames;
  ASSERT_GT(clustered, 0);
  const std::atomic<bool> cancel{true};
  for (int threads : {1, 4}) {
    const std::vector<JointClustering> joints = prepared->cluster(0, threshold, threads, &cancel);
    ASSERT_EQ(int(joints.size()), prepared->jointCount());
    for (const JointClustering& joint : joints)
      EXPECT_TRUE(joint.clusters.empty());
  }
}

// Guards bone reduction's per-joint loop (it ignored the flag: a long clip's frozen-pose
// search ran to its end after Ctrl+C): with the flag set it answers kCancelled, although the
// same call without it freezes joints of the tube.
TEST(Cancel, PresetFlagMakesBoneReductionReturnCancelled) {
  const BentTube bent;
  const double threshold = 1e6; // every joint of the tube holds one posture within this
  Result<BoneReduction> reduced = reduceBones(bent.tube.skeleton, bent.clips, threshold);
  ASSERT_TRUE(reduced) << reduced.message();
  ASSERT_GT(reduced->removedCount(), 0);
  const std::atomic<bool> cancel{true};
  reduced = reduceBones(bent.tube.skeleton, bent.clips, threshold, {}, 0, &cancel);
  ASSERT_FALSE(reduced);
  EXPECT_EQ(reduced.message(), kCancelled);
}

TEST(Cancel, PresetFlagStopsLodCharacter) {
  const BentTube bent;
  const std::atomic<bool> cancel{true};
  Result<LodCharacter> prepared = LodCharacter::prepare(bent.tube.skeleton, &bent.tube.mesh, bent.clips, {}, {}, &cancel);
  ASSERT_FALSE(prepared);
  EXPECT_EQ(prepared.message(), kCancelled);

  std::atomic<bool> later{false};
  Result<LodCharacter> character = LodCharacter::prepare(bent.tube.skeleton, &bent.tube.mesh, bent.clips, {}, {}, &later);
  ASSERT_TRUE(character) << character.message();
  later = true; // set after preparing: every later step sees it
  Result<LevelMotion> motion = character->motionAt(10.0);
  ASSERT_FALSE(motion);
  EXPECT_EQ(motion.message(), kCancelled);
  Result<LevelBuild> level = character->build(10.0, 0.5);
  ASSERT_FALSE(level);
  EXPECT_EQ(level.message(), kCancelled);
}

// The budget's search with the flag set: kLodBudgetCancelled before any progress, so before
// any work.
TEST(Cancel, PresetFlagMakesThePixelBudgetReturnCancelledWithoutWork) {
  const Asset asset = bentAsset();
  const std::atomic<bool> cancel{true};
  LodBudgetOptions options;
  options.cancel = &cancel;
  int calls = 0;
  options.progress = [&](double) { return ++calls, true; };
  Result<LodSet> lods = LodSet::fromPixelBudget(asset, 1.0, 4, options);
  ASSERT_FALSE(lods);
  EXPECT_EQ(lods.message(), kLodBudgetCancelled);
  EXPECT_EQ(calls, 0);
}

// The flag set while the search runs (here from its own progress, which keeps answering
// true): the search stops at its next look and reports no further progress.
TEST(Cancel, FlagSetDuringThePixelBudgetStopsIt) {
  const Asset asset = bentAsset();
  std::atomic<bool> cancel{false};
  LodBudgetOptions options;
  options.cancel = &cancel;
  double last = 0.0;
  int afterCancel = 0;
  options.progress = [&](double fraction) {
    if (cancel)
      ++afterCancel;
    last = fraction;
    if (fraction > 0.0)
      cancel = true;
    return true;
  };
  Result<LodSet> lods = LodSet::fromPixelBudget(asset, 1.0, 4, options);
  ASSERT_FALSE(lods);
  EXPECT_EQ(lods.message(), kLodBudgetCancelled);
  EXPECT_EQ(afterCancel, 0);
  EXPECT_LT(last, 1.0);
}

// The package: a preset flag gives kLodPackageCancelled, for a file's default set and for
// a given set alike, before any progress.
TEST(Cancel, PresetFlagMakesThePackageReturnCancelled) {
  const Asset asset = bentAsset();
  const std::atomic<bool> cancel{true};
  int calls = 0;
  const LodPackageProgress progress = [&](double, std::string_view) { return ++calls, true; };
  Result<LodPackage> package = buildLodPackage(asset, {}, progress, &cancel);
  ASSERT_FALSE(package);
  EXPECT_EQ(package.message(), kLodPackageCancelled);
  LodSet lods;
  lods.levels.resize(2);
  lods.levels[0].name = "LOD0";
  lods.levels[1].name = "LOD1";
  lods.levels[1].meshRatio = 0.5;
  lods.levels[1].motionThreshold = 10.0;
  package = buildLodPackage(asset, lods, {}, {}, progress, {}, &cancel);
  ASSERT_FALSE(package);
  EXPECT_EQ(package.message(), kLodPackageCancelled);
  EXPECT_EQ(calls, 0);
  // and without the flag the same set builds
  EXPECT_TRUE(buildLodPackage(asset, lods, {}, {}, progress)) << "the set given above must be valid";
}

} // namespace
} // namespace mlod
