// One error budget (docs/architecture.md section 5): deviations in cm against pixels on screen, and LOD
// sets generated from a pixel budget, checked by projecting the original and every level
// through a pinhole camera at the level's switch distance.

#include "core/lod/error_budget.h"
#include "core/lod/lod_character.h"
#include "core/lod/lod_levels.h"
#include "core/lod/lod_set.h"
#include "core/mesh/skinning.h"
#include "core/mesh/surface_distance.h"
#include "runtime/lod_selection.h"
#include "unit/core/mesh_lod_fixtures.h"
#include "unit/real_files.h"

#include <algorithm>
#include <cmath>
#include <gtest/gtest.h>
#include <iostream>
#include <numbers>
#include <stdexcept>

namespace mlod {
namespace {

// Guards the distance search against sizes without a distance: an infinite or NaN radius or
// deviation (../shared/repro/hang_offset_1e38_2frames.bvh gave an infinite height) doubled
// its upper end forever and `export` never ended; it answers "no distance" (infinity).
TEST(ErrorBudget, InfiniteSizesHaveNoDistanceAndDoNotHang) {
  const LodProjection projection;
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(distanceForPixels(1.0, 1.0, inf, projection), inf);
  EXPECT_EQ(distanceForPixels(inf, 1.0, 100.0, projection), inf);
  EXPECT_EQ(distanceForPixels(1.0, 1.0, nan, projection), inf);
  EXPECT_EQ(distanceForPixels(nan, 1.0, 100.0, projection), inf);
  // huge but finite sizes still get their (huge, finite) distance
  const double far = distanceForPixels(1e17, 1.0, 7.2e17, projection);
  EXPECT_TRUE(std::isfinite(far));
  EXPECT_NEAR(deviationPixels(1e17, far, 7.2e17, projection), 1.0, 1e-6);
}

TEST(ErrorBudget, PixelsFallWithDistanceAndTheInversesAgree) {
  const LodProjection projection; // 60 degrees, 1080 pixels
  EXPECT_NEAR(projection.focalPixels(), 1080.0 / (2.0 * std::tan(std::numbers::pi / 6.0)), 1e-9);
  const double radius = 100.0;
  double previous = std::numeric_limits<double>::infinity();
  for (double d : {150.0, 300.0, 1000.0, 10000.0}) {
    const double px = deviationPixels(1.0, d, radius, projection);
    EXPECT_LT(px, previous);
    previous = px;
    EXPECT_NEAR(deviationPixels(deviationForPixels(2.0, d, radius, projection), d, radius, projection), 2.0, 1e-6);
  }
  for (double deviation : {0.1, 1.0, 5.0}) {
    const double d = distanceForPixels(deviation, 1.0, radius, projection);
    EXPECT_NEAR(deviationPixels(deviation, d, radius, projection), 1.0, 1e-6);
    EXPECT_GT(deviationPixels(deviation, d * 0.99, radius, projection), 1.0);
  }
  // far away the bound is the plain pinhole one, f delta / d
  EXPECT_NEAR(deviationPixels(1.0, 1e6, radius, projection) / (projection.focalPixels() / 1e6), 1.0, 1e-3);
  EXPECT_EQ(deviationPixels(1.0, 50.0, radius, projection), std::numeric_limits<double>::infinity());
  // a level that deviates by nothing spans nothing, even from inside the sphere (its switch
  // distance is the radius): a finite figure that LodSet::validate() accepts
  EXPECT_EQ(deviationPixels(0.0, distanceForPixels(0.0, 1.0, radius, projection), radius, projection), 0.0);
  EXPECT_EQ(deviationPixels(0.0, 50.0, radius, projection), 0.0);
  // screen sizes are the runtime's
  EXPECT_NEAR(screenSizePixels(radius, 1000.0, projection), projectedSizePixels(100.0f, 1000.0f), 1e-3);
  EXPECT_NEAR(screenSizePixels(radius, distanceForScreenSize(radius, 270.0, projection), projection), 270.0, 1e-3);
}

// A pinhole camera at `distance` from `target`, looking at it along -direction.
struct Camera {
  glm::dvec3 eye, right, up, forward;
  double focal;
  Camera(const glm::dvec3& target, const glm::dvec3& direction, double distance, double focalPixels)
      : focal(focalPixels) {
    const glm::dvec3 back = glm::normalize(direction);
    eye = target + back * distance;
    forward = -back;
    const glm::dvec3 worldUp = std::abs(back.y) > 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(0, 1, 0);
    right = glm::normalize(glm::cross(forward, worldUp));
    up = glm::cross(right, forward);
  }
  glm::dvec2 project(const glm::dvec3& p) const {
    const glm::dvec3 v = p - eye;
    const double z = glm::dot(v, forward);
    return focal * glm::dvec2(glm::dot(v, right), glm::dot(v, up)) / z;
  }
};

// The largest on-screen distance (pixels) between sample points of one surface (vertices
// and triangle centroids) and their nearest points on the other, both ways.
double screenDeviation(const std::vector<glm::vec3>& aPositions, const std::vector<std::uint32_t>& aIndices,
                       const std::vector<glm::vec3>& bPositions, const std::vector<std::uint32_t>& bIndices,
                       const std::vector<Camera>& cameras) {
  double worst = 0.0;
  const auto oneWay = [&](const std::vector<glm::vec3>& fromPositions, const std::vector<std::uint32_t>& from,
                          const std::vector<glm::vec3>& toPositions, const std::vector<std::uint32_t>& to) {
    const TriangleTree tree(toPositions, to);
    std::vector<glm::dvec3> samples;
    for (std::uint32_t v : from)
      samples.emplace_back(fromPositions[v]);
    for (std::size_t t = 0; t + 2 < from.size(); t += 3)
      samples.push_back((glm::dvec3(fromPositions[from[t]]) + glm::dvec3(fromPositions[from[t + 1]]) +
                         glm::dvec3(fromPositions[from[t + 2]])) /
                        3.0);
    for (const glm::dvec3& p : samples) {
      int triangle = -1;
      tree.nearestSquared(p, std::numeric_limits<double>::infinity(), &triangle);
      const glm::dvec3 q = tree.closestPoint(p, triangle);
      for (const Camera& camera : cameras)
        worst = std::max(worst, glm::length(camera.project(p) - camera.project(q)));
    }
  };
  oneWay(aPositions, aIndices, bPositions, bIndices);
  oneWay(bPositions, bIndices, aPositions, aIndices);
  return worst;
}

class PixelBudget : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    Result<LodSet> set = LodSet::fromPixelBudget(test::bcnEpileptic(), 1.0, 4);
    ASSERT_TRUE(set) << set.message();
    s_set = new LodSet(std::move(set).value());
    for (const LodLevel& level : s_set->levels)
      std::cout << "[ level    ] " << level.name << ": E " << level.motionThreshold << ", mesh ratio "
                << level.meshRatio << " (" << level.triangles << " triangles), " << level.activeJoints
                << " joints, motion " << level.motionErrorCm << " cm + mesh " << level.meshErrorCm << " cm, from "
                << level.switchDistanceCm << " cm (" << level.screenSizePixels << " px high), " << level.pixelError
                << " px" << std::endl;
  }
  static void TearDownTestSuite() { delete s_set; }
  static LodSet* s_set;
};
LodSet* PixelBudget::s_set = nullptr;

TEST_F(PixelBudget, GeneratesAValidSetOfCoarseningLevels) {
  const LodSet& set = *s_set;
  EXPECT_FALSE(set.validate()) << set.validate().message();
  ASSERT_EQ(set.levels.size(), 4u);
  EXPECT_EQ(set.projection, LodProjection{});
  EXPECT_GT(set.boundingRadiusCm, 90.0); // a 1.8 m character about its pelvis
  for (std::size_t i = 1; i < set.levels.size(); ++i) {
    const LodLevel& level = set.levels[i];
    const LodLevel& finer = set.levels[i - 1];
    EXPECT_LE(level.pixelError, 1.0 + 1e-9);
    EXPECT_GE(level.switchDistanceCm, finer.switchDistanceCm);
    EXPECT_GE(level.motionThreshold, finer.motionThreshold);
    EXPECT_LE(level.triangles, finer.triangles);
    EXPECT_NEAR(level.pixelError,
                deviationPixels(level.deviationCm(), level.switchDistanceCm, set.boundingRadiusCm, set.projection),
                1e-9);
  }
  // the coarsest level simplifies something
  EXPECT_TRUE(set.levels.back().meshRatio < 1.0 || set.levels.back().motionThreshold > 0.0);
}

// Guards the mesh-led rule (issue 14): the far levels are the coarse ones (the ratios spread
// in log scale down to the smallest candidate: 50%, 20%, 10% for four levels; the far level
// kept 50% before), each coarser level switches strictly farther, and each level's measured
// deviation (motion + mesh) spans at most the budget at its switch distance and the full
// budget only there: a level never switches nearer than its error allows, nor farther. On
// every animated character of the shared fixture list (a dead level on another character
// than BCN_Epileptic at every budget was the bug this list is for).
class PixelBudgetOnCharacters : public ::testing::TestWithParam<std::string> {};

TEST_P(PixelBudgetOnCharacters, CoarserLevelsSwitchFartherWhereTheirMeasuredErrorFitsTheBudget) {
  Result<LodSet> generated = LodSet::fromPixelBudget(test::fixtureCharacter(GetParam()), 1.0, 4);
  ASSERT_TRUE(generated) << generated.message();
  const LodSet& set = *generated;
  const std::vector<std::string> stillOnes = test::fixtureCharacters("still");
  const bool still = std::find(stillOnes.begin(), stillOnes.end(), GetParam()) != stillOnes.end();
  ASSERT_EQ(set.levels.size(), 4u);
  const int total = set.levels.front().triangles;
  const double expected[] = {1.0, 0.5, 0.2, 0.1};
  for (std::size_t i = 1; i < set.levels.size(); ++i) {
    const LodLevel& level = set.levels[i];
    const LodLevel& finer = set.levels[i - 1];
    SCOPED_TRACE(level.name);
    EXPECT_NEAR(double(level.triangles) / total, expected[i], 0.05 * expected[i]);
    EXPECT_NEAR(level.meshRatio, double(level.triangles) / total, 1e-12);
    EXPECT_LT(level.triangles, finer.triangles);
    EXPECT_GT(level.meshErrorCm, finer.meshErrorCm);
    EXPECT_GT(level.switchDistanceCm, finer.switchDistanceCm);
    EXPECT_LE(deviationPixels(level.deviationCm(), level.switchDistanceCm, set.boundingRadiusCm, set.projection),
              1.0 + 1e-9);
    // the switch distance is where the deviation spans the budget, not a nearer or farther guess
    EXPECT_NEAR(level.switchDistanceCm,
                distanceForPixels(level.deviationCm(), 1.0, set.boundingRadiusCm, set.projection),
                1e-6 * level.switchDistanceCm);
    // motion within its share (0.5) of a deviation the mesh error sets on the full motion:
    // some of it where joints hold still, none where every joint turns all the time
    if (still)
      EXPECT_GT(level.motionErrorCm, 0.0);
    else
      EXPECT_EQ(level.motionErrorCm, 0.0);
  }
}

INSTANTIATE_TEST_SUITE_P(Characters, PixelBudgetOnCharacters, ::testing::ValuesIn(test::fixtureCharacters("animated")),
                         test::fixtureName);

TEST_F(PixelBudget, ProjectedAtItsSwitchDistanceEveryLevelStaysWithinTheBudget) {
  // rebuild each level from its figures alone, then look at the original and the level
  // through cameras around the character at the switch distance, in the poses the level was
  // measured in
  const Asset& asset = test::bcnEpileptic();
  const SkinnedMesh& mesh = asset.meshes.at(0);
  Result<LodCharacter> character = LodCharacter::prepare(asset.skeleton, &mesh, asset.clips);
  ASSERT_TRUE(character) << character.message();
  const double budget = 1.0;
  for (std::size_t i = 1; i < s_set->levels.size(); ++i) {
    const LodLevel& level = s_set->levels[i];
    SCOPED_TRACE(level.name);
    Result<LevelMotion> motion = character->motionAt(level.motionThreshold);
    ASSERT_TRUE(motion) << motion.message();
    Result<MeshLod> lod = character->meshLodFor(*motion);
    ASSERT_TRUE(lod) << lod.message();
    const MeshLodLevel simplified = lod->levelForRatio(level.meshRatio);
    ASSERT_EQ(int(simplified.triangles()), level.triangles);
    double worst = 0.0;
    for (const auto& [clip, frame] : lod->measureFrames()) {
      if (clip < 0)
        continue; // the bind pose is not a pose the character plays
      const std::vector<glm::vec3> original =
          posedPositions(mesh, asset.skeleton, asset.clips.at(std::size_t(clip)), frame);
      const std::vector<glm::vec3> shown =
          posedPositions(simplified.mesh, motion->bones.skeleton, motion->clips.at(std::size_t(clip)), frame);
      std::vector<glm::mat4> models;
      asset.clips.at(std::size_t(clip)).modelMatrices(asset.skeleton, frame, models);
      const glm::dvec3 root(models[0][3]);
      std::vector<Camera> cameras;
      for (const glm::dvec3& direction : {glm::dvec3(0, 0, 1), glm::dvec3(0, 0, -1), glm::dvec3(1, 0, 0),
                                          glm::dvec3(-1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(1, 1, 1)})
        cameras.emplace_back(root, direction, level.switchDistanceCm, s_set->projection.focalPixels());
      worst = std::max(worst, screenDeviation(original, mesh.indices, shown, simplified.mesh.indices, cameras));
    }
    std::cout << "[ project  ] " << level.name << ": at most " << worst << " px at " << level.switchDistanceCm << " cm"
              << std::endl;
    EXPECT_LE(worst, budget * (1.0 + 1e-6));
    EXPECT_GT(worst, 0.0);
  }
}

TEST_F(PixelBudget, EditedSetsAreValidated) {
  LodSet set = *s_set;
  set.levels[2].meshRatio = 0.0;
  EXPECT_TRUE(set.validate());
  set = *s_set;
  set.levels[2].switchDistanceCm = set.levels[1].switchDistanceCm - 1.0;
  EXPECT_TRUE(set.validate()) << "switch distances never fall";
  set = *s_set;
  set.levels[0].meshRatio = 0.5;
  EXPECT_TRUE(set.validate()) << "level 0 is the original";
  set = *s_set;
  set.levels[3].name = set.levels[1].name;
  EXPECT_TRUE(set.validate());
  set = *s_set;
  set.projection.verticalFovDegrees = 180.0;
  EXPECT_TRUE(set.validate());
  // a user's own edit within the rules stands
  set = *s_set;
  set.levels[1].motionThreshold = 7.5;
  set.levels[3].switchDistanceCm *= 2.0;
  EXPECT_FALSE(set.validate());
}

// A skeleton without a mesh (CMU 01_01): the table's thresholds are too coarse for its
// levels 2 and 3 (both fitted E = 10, the next step 20 missed), so the generator looks
// between them; no level repeats the one before it, and each still fits its budget.
TEST(PixelBudgetSkeleton, LevelsDoNotRepeatWhenTheThresholdStepsAreCoarse) {
  Result<LodSet> set = LodSet::fromPixelBudget(test::meshAsset("BVH/01_01.bvh"), 1.0, 4);
  ASSERT_TRUE(set) << set.message();
  EXPECT_FALSE(set->validate()) << set->validate().message();
  ASSERT_EQ(set->levels.size(), 4u);
  for (std::size_t i = 1; i < set->levels.size(); ++i) {
    const LodLevel& level = set->levels[i];
    std::cout << "[ level    ] " << level.name << ": E " << level.motionThreshold << ", motion " << level.motionErrorCm
              << " cm, from " << level.switchDistanceCm << " cm" << std::endl;
    EXPECT_LE(level.pixelError, 1.0 + 1e-9);
    if (i >= 2) {
      EXPECT_GT(level.motionThreshold, set->levels[i - 1].motionThreshold) << level.name;
    }
  }
}

// The rules of every generated set (lod_set.h): beyond LOD0 no level keeps the original's
// motion (E = 0) and none repeats the level before it (same E and mesh ratio); what is left
// out is reported, and every aimed level is either kept or reported.
void expectTheLevelRules(const LodSet& set, const LodBudgetReport& report, int aimed, bool hasMotion) {
  EXPECT_FALSE(set.validate()) << set.validate().message();
  EXPECT_EQ(set.levels.size() + report.dropped.size(), std::size_t(aimed));
  ASSERT_EQ(report.simplifiedPercent.size(), set.levels.size());
  EXPECT_EQ(report.simplifiedPercent[0], 0.0);
  for (std::size_t i = 1; i < set.levels.size(); ++i) {
    const LodLevel& level = set.levels[i];
    const LodLevel& previous = set.levels[i - 1];
    EXPECT_EQ(level.name, "LOD" + std::to_string(i));
    if (hasMotion) {
      EXPECT_GT(level.motionThreshold, 0.0) << level.name;
    }
    EXPECT_FALSE(level.motionThreshold == previous.motionThreshold && level.meshRatio == previous.meshRatio)
        << level.name << " repeats " << previous.name;
    // every level is used: it switches in strictly farther than the one before it
    EXPECT_GT(level.switchDistanceCm, previous.switchDistanceCm) << level.name << " leaves " << previous.name << " no distance";
    EXPECT_GE(report.simplifiedPercent[i], 0.0);
    EXPECT_LE(report.simplifiedPercent[i], 100.0);
  }
  for (const std::string& line : report.dropped)
    std::cout << "[ dropped  ] " << line << std::endl;
}

// The editor's sample (a CMU 01_01 excerpt, 1 inch = 2.54 / 0.45 cm): cheap to generate.
const Asset& sample() {
  static const Asset asset = [] {
    ImportOptions options;
    options.unitScale = 2.54 / 0.45;
    Result<Asset> imported = importAsset(MLOD_SAMPLE, options);
    if (!imported)
      throw std::runtime_error(std::string(MLOD_SAMPLE) + ": " + imported.message());
    return std::move(imported).value();
  }();
  return asset;
}

// A budget so tight that no threshold above 0 fits the nearest levels, one so loose that the
// threshold table runs out: the set holds fewer levels than asked rather than break a rule.
TEST(PixelBudgetRules, NoLevelKeepsTheOriginalMotionOrRepeatsItsPredecessor) {
  const Asset& asset = sample();
  const LodBudgetOptions options;
  for (double pixels : {0.02, 1.0, 40.0}) {
    LodBudgetReport report;
    Result<LodSet> set = LodSet::fromPixelBudget(asset, pixels, 6, options, &report);
    ASSERT_TRUE(set) << set.message();
    std::cout << "[ budget   ] " << pixels << " px: " << set->levels.size() << " levels, " << report.dropped.size()
              << " left out" << std::endl;
    expectTheLevelRules(*set, report, 6, true);
    // the report changes nothing of the set
    Result<LodSet> plain = LodSet::fromPixelBudget(asset, pixels, 6);
    ASSERT_TRUE(plain);
    EXPECT_TRUE(*plain == *set);
    if (pixels == 0.02) {
      EXPECT_FALSE(report.dropped.empty()) << "0.02 px leaves no room for any motion simplification";
    }
    if (set->levels.size() >= 3) {
      EXPECT_GT(report.simplifiedPercent.back(), report.simplifiedPercent[1]);
    }
  }
}

// Mesh levels alone (no clip): asked for more levels than there are candidate ratios, the
// ratios reach the candidates' floor, and a level that would repeat it is left out.
// The motion's share of a level's deviation is the pose's share of the frame cost (54 joints
// x 82 against 3,014 vertices x 29.4 instructions: 4.8%, clamped to 5%), not a fixed half:
// the same asset with the old fixed half gets larger thresholds and farther switch distances,
// because the mesh, which costs most of the frame, would get only half of each deviation.
TEST(PixelBudgetRules, TheMotionsShareOfTheDeviationFollowsTheFrameCost) {
  EXPECT_EQ(motionShareByCost(54, 3014), kMinMotionShare);
  EXPECT_NEAR(motionShareByCost(28, 471), 28 * 82.0 / (28 * 82.0 + 471 * 29.4), 1e-12); // the paper's crowd: 14%
  EXPECT_NEAR(motionShareByCost(28, 471), 0.142, 0.001);
  EXPECT_EQ(motionShareByCost(38, 0), kMaxMotionShare);
  EXPECT_EQ(motionShareByCost(0, 0), kMaxMotionShare);

  // the cost split is what a CPU-skinned character gets (the GPU's default: the next test)
  const Asset& asset = test::bcnEpileptic();
  LodBudgetReport byCost, half;
  LodBudgetOptions cpuOptions;
  cpuOptions.skinning = LodSkinning::Cpu;
  Result<LodSet> costSet = LodSet::fromPixelBudget(asset, 1.0, 3, cpuOptions, &byCost);
  ASSERT_TRUE(costSet) << costSet.message();
  LodBudgetOptions halfOptions;
  halfOptions.motionShare = 0.5;
  Result<LodSet> halfSet = LodSet::fromPixelBudget(asset, 1.0, 3, halfOptions, &half);
  ASSERT_TRUE(halfSet) << halfSet.message();
  EXPECT_EQ(byCost.motionShare, motionShareByCost(asset.skeleton.jointCount(), asset.meshes.at(0).vertexCount()));
  EXPECT_EQ(half.motionShare, 0.5);
  ASSERT_EQ(costSet->levels.size(), 3u);
  ASSERT_EQ(halfSet->levels.size(), 3u);
  for (std::size_t i = 1; i < 3; ++i) {
    SCOPED_TRACE(costSet->levels[i].name);
    const LodLevel& cost = costSet->levels[i];
    const LodLevel& old = halfSet->levels[i];
    EXPECT_EQ(cost.triangles, old.triangles) << "the mesh leads either way";
    EXPECT_GT(cost.motionThreshold, 0.0);
    EXPECT_LT(cost.motionThreshold, old.motionThreshold);
    EXPECT_LT(cost.motionErrorCm, old.motionErrorCm);
    EXPECT_LT(cost.switchDistanceCm, old.switchDistanceCm) << "the level starts nearer";
  }
}

// Guards the default (issue 25): skinned on the GPU, as engines do, the CPU pays the pose
// alone and the motion takes a stated half of each level's deviation, not the 5% of a
// CPU-skinned frame; an explicit share still overrides it; the set says what it assumed.
TEST(PixelBudgetRules, SkinnedOnTheGpuTheMotionTakesHalfTheDeviation) {
  EXPECT_EQ(kGpuMotionShare, 0.5);
  const Asset& asset = test::bcnEpileptic();
  const LodBudgetOptions defaults;
  EXPECT_EQ(defaults.skinning, LodSkinning::Gpu);
  LodBudgetReport gpu, explicitHalf, cpu, overridden;
  Result<LodSet> gpuSet = LodSet::fromPixelBudget(asset, 1.0, 3, defaults, &gpu);
  ASSERT_TRUE(gpuSet) << gpuSet.message();
  EXPECT_EQ(gpu.motionShare, kGpuMotionShare);
  EXPECT_EQ(gpuSet->skinning, LodSkinning::Gpu);

  LodBudgetOptions halfOptions;
  halfOptions.skinning = LodSkinning::Cpu;
  halfOptions.motionShare = 0.5;
  Result<LodSet> halfSet = LodSet::fromPixelBudget(asset, 1.0, 3, halfOptions, &explicitHalf);
  ASSERT_TRUE(halfSet) << halfSet.message();
  EXPECT_EQ(halfSet->levels, gpuSet->levels) << "the GPU's default is the same search as an explicit half";
  EXPECT_EQ(halfSet->skinning, LodSkinning::Cpu);

  LodBudgetOptions cpuOptions;
  cpuOptions.skinning = LodSkinning::Cpu;
  Result<LodSet> cpuSet = LodSet::fromPixelBudget(asset, 1.0, 3, cpuOptions, &cpu);
  ASSERT_TRUE(cpuSet) << cpuSet.message();
  EXPECT_EQ(cpu.motionShare, motionShareByCost(asset.skeleton.jointCount(), asset.meshes.at(0).vertexCount()));
  EXPECT_EQ(cpuSet->skinning, LodSkinning::Cpu);

  LodBudgetOptions gpuOverride;
  gpuOverride.motionShare = 0.2;
  Result<LodSet> overriddenSet = LodSet::fromPixelBudget(asset, 1.0, 3, gpuOverride, &overridden);
  ASSERT_TRUE(overriddenSet) << overriddenSet.message();
  EXPECT_EQ(overridden.motionShare, 0.2) << "an explicit share wins over the skinning's";

  // without a mesh the motion takes all of it, wherever skinning runs
  Asset skeletonOnly = asset;
  skeletonOnly.meshes.clear();
  LodBudgetReport alone;
  Result<LodSet> aloneSet = LodSet::fromPixelBudget(skeletonOnly, 1.0, 3, defaults, &alone);
  ASSERT_TRUE(aloneSet) << aloneSet.message();
  EXPECT_EQ(alone.motionShare, 1.0);
}

TEST(PixelBudgetRules, SkinningNamesReadBack) {
  for (LodSkinning skinning : {LodSkinning::Gpu, LodSkinning::Cpu})
    EXPECT_EQ(lodSkinningFromName(lodSkinningName(skinning)), skinning);
  EXPECT_STREQ(lodSkinningName(LodSkinning::Gpu), "gpu");
  EXPECT_STREQ(lodSkinningName(LodSkinning::Cpu), "cpu");
  EXPECT_EQ(lodSkinningFromName("GPU"), std::nullopt);
  EXPECT_EQ(lodSkinningFromName(""), std::nullopt);
  EXPECT_EQ(lodSkinningFromName("both"), std::nullopt);
}

TEST(PixelBudgetRules, MeshOnlyLevelsDoNotRepeat) {
  Asset noClip = test::bcnEpileptic();
  noClip.clips.clear();
  const LodBudgetOptions options;
  const int aimed = static_cast<int>(options.meshRatios.size()) + 3;
  LodBudgetReport report;
  Result<LodSet> set = LodSet::fromPixelBudget(noClip, 1.0, aimed, options, &report);
  ASSERT_TRUE(set) << set.message();
  expectTheLevelRules(*set, report, aimed, false);
  EXPECT_FALSE(report.dropped.empty()) << aimed << " levels over " << options.meshRatios.size() << " ratios";
}

// Progress rises to 1; returning false cancels at once with kLodBudgetCancelled.
TEST(PixelBudgetRules, ProgressRisesAndCancels) {
  const Asset& asset = sample();
  std::vector<double> seen;
  LodBudgetOptions options;
  options.progress = [&](double fraction) {
    seen.push_back(fraction);
    return true;
  };
  ASSERT_TRUE(LodSet::fromPixelBudget(asset, 1.0, 4, options));
  ASSERT_GE(seen.size(), 5u);
  EXPECT_EQ(seen.front(), 0.0);
  EXPECT_EQ(seen.back(), 1.0);
  EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
  int calls = 0;
  options.progress = [&](double) { return ++calls < 3; };
  Result<LodSet> cancelled = LodSet::fromPixelBudget(asset, 1.0, 4, options);
  ASSERT_FALSE(cancelled);
  EXPECT_EQ(cancelled.message(), kLodBudgetCancelled);
  EXPECT_EQ(calls, 3) << "no work after the cancel";
}

TEST(PixelBudgetRules, OverridesAboveTheirLevelAreListed) {
  LodSet set;
  set.levels.resize(3);
  set.levels[0].name = "LOD0";
  set.levels[1] = {.name = "LOD1", .motionThreshold = 10.0};
  set.levels[2] = {.name = "LOD2", .motionThreshold = 50.0};
  JpcSettings settings;
  settings.joints["Neck"].thresholds = {std::nullopt, 20.0, 40.0};        // above LOD1's 10, below LOD2's 50
  settings.joints["Head"].thresholds = {std::nullopt, 10.0, 80.0, 500.0}; // equal at LOD1; LOD3 is not in the set
  settings.joints["Hips"].locked = true;
  const std::vector<LodOverrideAbove> above = overridesAboveLevels(settings, set);
  const std::vector<LodOverrideAbove> expected = {{"Neck", 1, 20.0, 10.0}, {"Head", 2, 80.0, 50.0}};
  EXPECT_EQ(above, expected);
}

// Guards the work cap of the budget's search (issue 29: `export` of 3DS mutants whose one
// joint got 19,725 and 39,455 frames ran past 60 s, clustering threshold after threshold,
// where `simplify` of them ends in seconds): a search that would spend more than
// LodBudgetOptions::workLimit is refused, naming the limit; the default lets it through.
TEST(PixelBudgetInput, SearchPastItsWorkLimitIsRefused) {
  const Asset& asset = sample();
  LodBudgetOptions options;
  options.workLimit = 1000;
  const Result<LodSet> refused = LodSet::fromPixelBudget(asset, 1.0, 4, options);
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.message().find("needs more work"), std::string::npos) << refused.message();
  EXPECT_NE(refused.message().find("1000 units"), std::string::npos) << refused.message();
  options.workLimit = kMaxJpcWork;
  const Result<LodSet> passed = LodSet::fromPixelBudget(asset, 1.0, 4, options);
  EXPECT_TRUE(passed) << passed.message();
}

TEST(PixelBudgetInput, BadRequestsAreErrors) {
  const Asset& asset = test::bcnEpileptic();
  EXPECT_FALSE(LodSet::fromPixelBudget(asset, 0.0, 4));
  EXPECT_FALSE(LodSet::fromPixelBudget(asset, 1.0, 0));
  LodBudgetOptions options;
  options.motionShare = 0.0;
  EXPECT_FALSE(LodSet::fromPixelBudget(asset, 1.0, 3, options));
  Asset nothing;
  nothing.skeleton = asset.skeleton;
  EXPECT_FALSE(LodSet::fromPixelBudget(nothing, 1.0, 3)) << "neither a clip nor a mesh";
  // a character that plays no clip gets mesh levels alone, measured in its bind pose
  Asset noClip = asset;
  noClip.clips.clear();
  Result<LodSet> meshOnly = LodSet::fromPixelBudget(noClip, 1.0, 3);
  ASSERT_TRUE(meshOnly) << meshOnly.message();
  EXPECT_FALSE(meshOnly->validate());
  ASSERT_EQ(meshOnly->levels.size(), 3u);
  EXPECT_EQ(meshOnly->levels[2].motionThreshold, 0.0);
  EXPECT_LT(meshOnly->levels[2].meshRatio, 1.0);
  EXPECT_LE(meshOnly->levels[2].pixelError, 1.0 + 1e-9);
  // one level is the original alone
  Result<LodSet> one = LodSet::fromPixelBudget(asset, 1.0, 1);
  ASSERT_TRUE(one) << one.message();
  EXPECT_EQ(one->levels.size(), 1u);
}

} // namespace
} // namespace mlod
