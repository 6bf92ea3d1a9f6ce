// Bone reduction per LOD level: joints frozen in every clip go, their skin is rebound with the
// frozen pose baked in, and the reduced character renders like the full one within the
// level's error.

#include "core/jpc/simplified_motion.h"
#include "core/lod/bone_reduction.h"
#include "core/lod/lod_character.h"
#include "core/mapping/motion_mapping.h"
#include "unit/core/mesh_lod_fixtures.h"
#include "unit/real_files.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>
#include <tuple>

namespace mlod {
namespace {

// Linear blend skinning written out here, independent of core's: models x inverse bind.
std::vector<glm::vec3> renderLbs(const Skeleton& skeleton, const Clip& clip, int frame, const SkinnedMesh& mesh) {
  std::vector<glm::mat4> models;
  clip.modelMatrices(skeleton, frame, models);
  const std::vector<glm::mat4> rest = skeleton.restModelMatrices();
  std::vector<glm::vec3> out(mesh.vertexCount());
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    glm::dvec3 sum(0.0);
    for (int i = 0; i < 4; ++i) {
      const float w = mesh.weights[v][i];
      if (w == 0.0f)
        continue;
      const std::size_t j = mesh.joints[v][i];
      const glm::mat4 inverseBind = skeleton.joints[j].inverseBind ? *skeleton.joints[j].inverseBind : glm::inverse(rest[j]);
      sum += double(w) * glm::dvec3(models[j] * inverseBind * glm::vec4(mesh.positions[v], 1.0f));
    }
    out[v] = glm::vec3(sum);
  }
  return out;
}

double maxDistance(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
  double worst = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i)
    worst = std::max(worst, double(glm::length(a[i] - b[i])));
  return worst;
}

// The tube whose upper joint holds a 30 degree bend while the lower one (the root) turns.
Clip tubeHoldClip(const Skeleton& skeleton, float wobbleDegrees = 0.0f) {
  Clip clip = Clip::restPose(skeleton, 20, 30.0);
  clip.name = "hold";
  clip.hasRotation = {1, 1};
  for (int t = 0; t < clip.frameCount; ++t) {
    clip.rotations[clip.index(0, t)] = glm::angleAxis(glm::radians(4.0f * float(t)), glm::vec3(0.0f, 1.0f, 0.0f));
    const float bend = 30.0f + wobbleDegrees * std::sin(float(t));
    clip.rotations[clip.index(1, t)] = glm::angleAxis(glm::radians(bend), glm::vec3(0.0f, 0.0f, 1.0f));
  }
  return clip;
}

TEST(BoneReduction, AJointHeldStillGoesAndTheSkinFollowsExactly) {
  const test::Tube tube = test::makeTube();
  const Clip clip = tubeHoldClip(tube.skeleton);
  Result<BoneReduction> reduction = reduceBones(tube.skeleton, std::span<const Clip>(&clip, 1), 0.0);
  ASSERT_TRUE(reduction) << reduction.message();
  ASSERT_EQ(reduction->removedCount(), 1);
  EXPECT_EQ(reduction->removed[1], 1);
  EXPECT_EQ(reduction->removed[0], 0) << "the root never goes";
  EXPECT_EQ(reduction->skeleton.jointCount(), 1);
  EXPECT_FALSE(reduction->skeleton.validate());
  const SkinnedMesh rebound = rebindMesh(*reduction, tube.skeleton, tube.mesh);
  ASSERT_FALSE(rebound.validate(1)) << rebound.validate(1).message();
  const Clip reduced = reduceClip(*reduction, tube.skeleton, clip);
  ASSERT_FALSE(reduced.validate(reduction->skeleton)) << reduced.validate(reduction->skeleton).message();
  // every influence ends on the root, so the baked skin is exact in every pose
  for (int t = 0; t < clip.frameCount; t += 3)
    EXPECT_LT(maxDistance(renderLbs(tube.skeleton, clip, t, tube.mesh),
                          renderLbs(reduction->skeleton, reduced, t, rebound)),
              1e-4)
        << "frame " << t;
}

TEST(BoneReduction, AJointMovingMoreThanTheBoundStays) {
  const test::Tube tube = test::makeTube();
  const Clip clip = tubeHoldClip(tube.skeleton, 2.0f); // +-2 degrees about a 30 degree bend
  // E of "upper" (no child: r = 0) is alpha x angle: 5 cm x up to 4 degrees = 20 cm·degrees apart,
  // so a pose within 10 of every frame exists, and none within 5
  Result<BoneReduction> tight = reduceBones(tube.skeleton, std::span<const Clip>(&clip, 1), 5.0);
  ASSERT_TRUE(tight) << tight.message();
  EXPECT_EQ(tight->removedCount(), 0);
  Result<BoneReduction> loose = reduceBones(tube.skeleton, std::span<const Clip>(&clip, 1), 12.0);
  ASSERT_TRUE(loose) << loose.message();
  EXPECT_EQ(loose->removedCount(), 1);
  EXPECT_LE(loose->frozenError[1], 12.0);
  // a locked joint never goes
  JpcSettings settings;
  settings.joints["upper"].locked = true;
  Result<BoneReduction> locked = reduceBones(tube.skeleton, std::span<const Clip>(&clip, 1), 1000.0, settings);
  ASSERT_TRUE(locked) << locked.message();
  EXPECT_EQ(locked->removedCount(), 0);
}

TEST(BoneReduction, AJointWithAnAnimatedTranslationStays) {
  const test::Tube tube = test::makeTube();
  Clip clip = tubeHoldClip(tube.skeleton);
  clip.hasTranslation[1] = 1;
  for (int t = 0; t < clip.frameCount; ++t)
    clip.translations[clip.index(1, t)] = glm::vec3(0.0f, 20.0f + 0.5f * float(t), 0.0f);
  Result<BoneReduction> reduction = reduceBones(tube.skeleton, std::span<const Clip>(&clip, 1), 1000.0);
  ASSERT_TRUE(reduction) << reduction.message();
  EXPECT_EQ(reduction->removedCount(), 0);
}

TEST(BoneReduction, BadInputIsAnError) {
  const test::Tube tube = test::makeTube(5, 8);
  const Clip clip = tubeHoldClip(tube.skeleton);
  EXPECT_FALSE(reduceBones(tube.skeleton, {}, 1.0)) << "no clip";
  EXPECT_FALSE(reduceBones(tube.skeleton, std::span<const Clip>(&clip, 1), -1.0));
  EXPECT_FALSE(reduceBones(test::bcnEpileptic().skeleton, std::span<const Clip>(&clip, 1), 1.0)) << "wrong skeleton";
}

// BCN_Epileptic's own clip and CMU 01_01 played on it through the committed mapping.
Result<std::vector<Clip>> bcnOwnClipAndMappedWalk() {
  const Asset& bcn = test::bcnEpileptic();
  const Asset& cmu = test::meshAsset("BVH/01_01.bvh");
  std::ifstream in(std::string(MLOD_TEST_DATA_DIR) + "/mappings/cmu_01_01_to_bcn_epileptic.json");
  std::stringstream text;
  text << in.rdbuf();
  Result<MotionMapping> mapping = motionMappingFromJson(text.str());
  if (!mapping)
    return mapping.error();
  Result<RestPoseDifferences> differences = restPoseDifferences(*mapping, cmu.skeleton, bcn.skeleton);
  if (!differences)
    return differences.error();
  Result<Clip> walk = retargetClip(*differences, cmu.skeleton, cmu.clips.at(0), bcn.skeleton);
  if (!walk)
    return walk.error();
  return std::vector<Clip>{bcn.clips.at(0), *walk};
}

TEST(BoneReductionClips, AJointGoesOnlyWhenFrozenInEveryClip) {
  // BCN_Epileptic's own clip and CMU 01_01 played on it through the committed mapping: a
  // joint goes at a threshold only if one pose holds within it in both
  const Asset& bcn = test::bcnEpileptic();
  const Result<std::vector<Clip>> clips = bcnOwnClipAndMappedWalk();
  ASSERT_TRUE(clips) << clips.message();
  const std::vector<Clip>& both = *clips;
  for (double threshold : {0.0, 2.0, 20.0}) {
    Result<BoneReduction> own = reduceBones(bcn.skeleton, std::span<const Clip>(&both[0], 1), threshold);
    Result<BoneReduction> mapped = reduceBones(bcn.skeleton, std::span<const Clip>(&both[1], 1), threshold);
    Result<BoneReduction> all = reduceBones(bcn.skeleton, both, threshold);
    ASSERT_TRUE(own && mapped && all);
    int shared = 0;
    for (std::size_t j = 0; j < all->removed.size(); ++j) {
      if (all->removed[j]) {
        EXPECT_TRUE(own->removed[j] && mapped->removed[j]) << bcn.skeleton.joints[j].name;
        EXPECT_LE(all->frozenError[j], threshold);
      }
      shared += own->removed[j] && mapped->removed[j];
    }
    std::cout << "[ removed  ] threshold " << threshold << ": own clip " << own->removedCount() << ", mapped walk "
              << mapped->removedCount() << ", both " << all->removedCount() << " of " << bcn.skeleton.jointCount()
              << std::endl;
    if (threshold > 0.0) { // at 0 the face holds one pose in its own clip and the rest pose in the walk
      EXPECT_GT(all->removedCount(), 0) << "the face joints hold still in both";
    }
    EXPECT_LE(all->removedCount(), shared);
    EXPECT_LT(all->removedCount(), own->removedCount()) << "the walk moves joints BCN's own clip holds still";
  }
}

// Guards BoneReductionCache (a pixel budget's search reduces the bones at ten thresholds and
// more): through one cache, thresholds asked in any order (rising, falling, again, per-level
// overrides, another alpha) give every field of the reduction as a call without it does.
// Mutation checked: answering a found pose without comparing its error with the threshold
// fails here.
TEST(BoneReductionCache, EveryThresholdInAnyOrderGivesWhatACallWithoutItGives) {
  const Asset& bcn = test::bcnEpileptic();
  const Result<std::vector<Clip>> clips = bcnOwnClipAndMappedWalk();
  ASSERT_TRUE(clips) << clips.message();
  const std::vector<Clip>& both = *clips;
  JpcSettings overrides;
  overrides.joints[bcn.skeleton.joints.at(3).name].thresholds = {std::nullopt, 400.0};
  JpcSettings stiff;
  stiff.joints[bcn.skeleton.joints.at(2).name].alpha = 10.0;
  BoneReductionCache cache;
  int removedSomewhere = 0;
  // falling in small steps (a pose found at one threshold may be beyond the next), rising,
  // again, per-level overrides, another alpha
  std::vector<std::tuple<double, JpcSettings, int>> asked;
  for (double threshold = 300.0; threshold > 0.5; threshold *= 0.8)
    asked.emplace_back(threshold, JpcSettings{}, 0);
  for (double threshold : {0.0, 2.0, 20.0, 50.0, 1000.0})
    asked.emplace_back(threshold, JpcSettings{}, 0);
  asked.emplace_back(5.0, overrides, 1);
  asked.emplace_back(5.0, overrides, 0);
  asked.emplace_back(20.0, stiff, 0);
  asked.emplace_back(20.0, JpcSettings{}, 0);
  for (const auto& [threshold, settings, level] : asked) {
    SCOPED_TRACE("threshold " + std::to_string(threshold) + " level " + std::to_string(level));
    Result<BoneReduction> plain = reduceBones(bcn.skeleton, both, threshold, settings, level);
    Result<BoneReduction> cached = reduceBones(bcn.skeleton, both, threshold, settings, level, nullptr, &cache);
    ASSERT_TRUE(plain && cached);
    EXPECT_EQ(cached->removed, plain->removed);
    EXPECT_EQ(cached->frozenRotation, plain->frozenRotation);
    EXPECT_EQ(cached->frozenError, plain->frozenError);
    EXPECT_EQ(cached->reducedIndex, plain->reducedIndex);
    EXPECT_EQ(cached->fullIndex, plain->fullIndex);
    EXPECT_EQ(cached->activeAncestor, plain->activeAncestor);
    removedSomewhere += plain->removedCount();
  }
  EXPECT_GT(removedSomewhere, 0);
}

class BcnBoneReduction : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    const Asset& asset = test::bcnEpileptic();
    Result<LodCharacter> character = LodCharacter::prepare(asset.skeleton, &asset.meshes.at(0), asset.clips);
    ASSERT_TRUE(character) << character.message();
    s_character = new LodCharacter(std::move(character).value());
  }
  static void TearDownTestSuite() { delete s_character; }
  static LodCharacter* s_character;
};
LodCharacter* BcnBoneReduction::s_character = nullptr;

TEST_F(BcnBoneReduction, TheReducedCharacterRendersLikeTheFullOneWithinTheLevelsError) {
  const Asset& asset = test::bcnEpileptic();
  const SkinnedMesh& mesh = asset.meshes.at(0);
  for (double threshold : {5.0, 50.0}) {
    SCOPED_TRACE("threshold " + std::to_string(threshold));
    Result<LevelMotion> level = s_character->motionAt(threshold);
    ASSERT_TRUE(level) << level.message();
    const BoneReduction& bones = level->bones;
    EXPECT_GT(bones.removedCount(), 0);
    EXPECT_FALSE(bones.skeleton.validate());
    ASSERT_TRUE(level->mesh);
    ASSERT_FALSE(level->mesh->validate(bones.skeleton.jointCount())) << level->mesh->validate(bones.skeleton.jointCount()).message();
    const Clip& reduced = level->clips.at(0);
    ASSERT_FALSE(reduced.validate(bones.skeleton));
    // every removed joint holds a pose within the bound of every frame
    for (std::size_t j = 0; j < bones.removed.size(); ++j)
      if (bones.removed[j]) {
        EXPECT_LE(bones.frozenError[j], threshold) << asset.skeleton.joints[j].name;
      }
    // the level's error bounds what a render shows, frame by frame
    const Clip& original = asset.clips.at(0);
    const Clip full = frozenClip(bones, simplifiedClip(original, level->clusters.at(0)));
    double worst = 0.0, worstExact = 0.0;
    for (int t = 0; t < original.frameCount; t += 7) {
      const std::vector<glm::vec3> a = renderLbs(asset.skeleton, original, t, mesh);
      const std::vector<glm::vec3> b = renderLbs(bones.skeleton, reduced, t, *level->mesh);
      const std::vector<glm::vec3> c = renderLbs(asset.skeleton, full, t, mesh);
      worst = std::max(worst, maxDistance(a, b));
      // where every influence ends on one active joint the baking is exact: the reduced
      // render is the full skeleton's render of the same motion
      for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
        int target = -1;
        bool single = true;
        for (int i = 0; i < 4; ++i)
          if (mesh.weights[v][i] > 0.0f) {
            const int active = bones.activeAncestor[mesh.joints[v][i]];
            single &= target < 0 || target == active;
            target = active;
          }
        if (single)
          worstExact = std::max(worstExact, double(glm::length(b[v] - c[v])));
      }
    }
    EXPECT_LE(worst, level->motionErrorCm + 1e-4);
    EXPECT_LT(worstExact, 1e-3);
    EXPECT_GT(level->motionErrorCm, 0.0);
  }
}

// Guards the weight transfer: every influence of the rebound mesh is a joint the level
// keeps (removed bones' weights went to their nearest kept ancestor, normalised), and the
// mesh LOD of that mesh still reaches its far ratios; a coarser threshold never keeps more
// joints. On every character of the shared fixture list (unit/real_files.h) with joints that
// hold still (a level that freezes none has nothing to rebind).
class BoneReductionOnCharacters : public ::testing::TestWithParam<std::string> {};

TEST_P(BoneReductionOnCharacters, AReducedLevelsMeshIsBoundToActiveJointsAndSimplifiesToTenPercent) {
  const Asset& asset = test::fixtureCharacter(GetParam());
  ASSERT_EQ(asset.meshes.size(), 1u);
  Result<LodCharacter> character = LodCharacter::prepare(asset.skeleton, &asset.meshes.at(0), asset.clips);
  ASSERT_TRUE(character) << character.message();
  Result<LevelMotion> level = character->motionAt(50.0);
  ASSERT_TRUE(level) << level.message();
  ASSERT_GT(level->bones.removedCount(), 0) << "50 cm freezes no joint: nothing to rebind";
  ASSERT_TRUE(level->mesh);
  EXPECT_FALSE(level->mesh->validate(level->bones.skeleton.jointCount()));
  // each vertex is bound to the kept ancestors of the joints it was bound to, and only to them
  const SkinnedMesh& original = asset.meshes[0];
  const BoneReduction& bones = level->bones;
  ASSERT_EQ(level->mesh->vertexCount(), original.vertexCount());
  for (std::size_t v = 0; v < original.vertexCount(); ++v) {
    std::set<int> expected, bound;
    for (int i = 0; i < 4; ++i) {
      if (original.weights[v][i] > 0.0f)
        expected.insert(bones.reducedIndex[std::size_t(bones.activeAncestor[original.joints[v][i]])]);
      if (level->mesh->weights[v][i] > 0.0f)
        bound.insert(int(level->mesh->joints[v][i]));
    }
    ASSERT_EQ(bound, expected) << "vertex " << v;
  }
  Result<MeshLod> reduced = character->meshLodFor(*level);
  ASSERT_TRUE(reduced) << reduced.message();
  const MeshLodLevel far = reduced->levelForRatio(0.1);
  EXPECT_TRUE(far.warning.empty()) << far.warning;
  EXPECT_LE(double(far.triangles()), 1.05 * 0.1 * double(level->mesh->triangleCount()));
  Result<LevelMotion> coarse = character->motionAt(500.0);
  ASSERT_TRUE(coarse);
  EXPECT_GE(coarse->bones.removedCount(), level->bones.removedCount());
}

INSTANTIATE_TEST_SUITE_P(Characters, BoneReductionOnCharacters, ::testing::ValuesIn(test::fixtureCharacters("still")),
                         test::fixtureName);

} // namespace
} // namespace mlod
