// The motion error of a level (core/lod/skin_deviation.h) is the plain maximum, to the bit,
// and its bound (what the pixel budget compares E = 0's noise-level error by) is above it:
// on skinned characters of Debian's assimp-testmodels playing their own clips and CMU 01_03
// mapped onto them, at thresholds from 0 (float noise only: every frame counts) to 1000
// (bones removed, vertices blending joints rebound to different ones), the bounded search
// gives exactly what skinning both renders in every frame gives. Before it, every candidate
// threshold of a pixel budget skinned the original and the level mesh in all 4,511 frames.

#include "core/cancel.h"
#include "core/lod/lod_character.h"
#include "core/lod/skin_deviation.h"
#include "core/mapping/motion_mapping.h"
#include "core/mesh/skinning.h"
#include "unit/core/mesh_lod_fixtures.h"

#include <atomic>
#include <gtest/gtest.h>
#include <stdexcept>
#include <string>
#include <vector>

namespace mlod {
namespace {

// The plain loop: both renders in every frame, the largest float distance.
double plainDeviation(const Skeleton& skeleton, const SkinnedMesh& mesh, const Clip& clip, const LevelMotion& level,
                      const Clip& levelClip) {
  double largest = 0.0;
  std::vector<glm::mat4> models;
  std::vector<glm::vec3> original, simplified;
  for (int t = 0; t < clip.frameCount; ++t) {
    clip.modelMatrices(skeleton, t, models);
    skinPositions(mesh, skinningPalette(skeleton, models), original);
    levelClip.modelMatrices(level.bones.skeleton, t, models);
    skinPositions(*level.mesh, skinningPalette(level.bones.skeleton, models), simplified);
    for (std::size_t v = 0; v < original.size(); ++v)
      largest = std::max(largest, double(glm::length(simplified[v] - original[v])));
  }
  return largest;
}

const SkinnedMesh& skinnedMesh(const Asset& asset) {
  for (const SkinnedMesh& mesh : asset.meshes)
    if (mesh.skinned())
      return mesh;
  throw std::runtime_error("no skinned mesh");
}

class SkinDeviationOnCharacters : public ::testing::TestWithParam<std::string> {};

TEST_P(SkinDeviationOnCharacters, IsThePlainMaximumAtEveryThreshold) {
  const Asset& asset = test::meshAsset(GetParam());
  const Asset& motion = test::meshAsset("BVH/01_03.bvh");
  Result<MappedMotion> mapped =
      mapMotionAutomatically(motion.skeleton, std::span<const Clip>(motion.clips).first(1), asset.skeleton, GetParam());
  ASSERT_TRUE(mapped) << mapped.message();
  std::vector<Clip> clips = asset.clips;
  clips.insert(clips.end(), mapped->clips.begin(), mapped->clips.end());
  const SkinnedMesh& mesh = skinnedMesh(asset);
  JpcSettings jpc;
  jpc.zeroLength = 1e-6 * asset.unitScale;
  Result<LodCharacter> character = LodCharacter::prepare(asset.skeleton, &mesh, clips, jpc);
  ASSERT_TRUE(character) << character.message();
  const SkinDeviation deviation(mesh);
  bool blended = false;
  for (const double threshold : {0.0, 2.0, 10.0, 50.0, 300.0, 1000.0}) {
    SCOPED_TRACE(GetParam() + " E=" + std::to_string(threshold));
    Result<LevelMotion> level = character->motionAt(threshold);
    ASSERT_TRUE(level) << level.message();
    ASSERT_TRUE(level->mesh);
    double plain = 0.0;
    for (std::size_t c = 0; c < clips.size(); ++c) {
      const double alone = plainDeviation(asset.skeleton, mesh, clips[c], *level, level->clips[c]);
      plain = std::max(plain, alone);
      Result<double> bounded =
          deviation.measure(asset.skeleton, mesh, clips[c], level->bones, *level->mesh, level->clips[c], 0.0);
      ASSERT_TRUE(bounded) << bounded.message();
      EXPECT_EQ(*bounded, alone) << "clip " << clips[c].name;
    }
    EXPECT_EQ(level->motionErrorCm, plain); // what LodCharacter::motionAt() reports
    // the bound alone (the budget's E = 0) is at least that, and measuring it gives it exactly
    Result<LevelMotion> bounded = character->motionAt(threshold, 0, LodCharacter::MotionError::Bound);
    ASSERT_TRUE(bounded) << bounded.message();
    EXPECT_FALSE(bounded->motionErrorExact);
    EXPECT_GE(bounded->motionErrorCm, plain);
    EXPECT_FALSE(character->measureMotionError(*bounded));
    EXPECT_TRUE(bounded->motionErrorExact);
    EXPECT_EQ(bounded->motionErrorCm, plain);
    blended = blended || level->bones.removedCount() > 0;
  }
  EXPECT_TRUE(blended) << "no threshold removed a joint: the rebound vertices went untested";
}

INSTANTIATE_TEST_SUITE_P(Characters, SkinDeviationOnCharacters, ::testing::Values("X/BCN_Epileptic.X", "X/Testwuson.X"),
                         [](const ::testing::TestParamInfo<std::string>& param) {
                           std::string name = param.param.substr(param.param.rfind('/') + 1);
                           return name.substr(0, name.find('.'));
                         });

// Cancelling stops the measurement with kCancelled.
TEST(SkinDeviation, StopsWhenCancelled) {
  const Asset& asset = test::bcnEpileptic();
  const SkinnedMesh& mesh = skinnedMesh(asset);
  Result<LodCharacter> character = LodCharacter::prepare(asset.skeleton, &mesh, asset.clips);
  ASSERT_TRUE(character) << character.message();
  Result<LevelMotion> level = character->motionAt(50.0);
  ASSERT_TRUE(level) << level.message();
  const std::atomic<bool> cancel{true};
  Result<double> measured = SkinDeviation(mesh).measure(asset.skeleton, mesh, asset.clips.front(), level->bones,
                                                        *level->mesh, level->clips.front(), 0.0, &cancel);
  ASSERT_FALSE(measured);
  EXPECT_EQ(measured.message(), kCancelled);
}

} // namespace
} // namespace mlod
