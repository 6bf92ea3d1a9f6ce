// Level edits of a LOD set (core/lod/lod_levels.h): the rules of the LOD Levels dock, each
// checked without the editor. Every edit leaves a set that LodSet::validate() accepts.

#include "core/lod/lod_levels.h"
#include "core/project.h"

#include <cmath>
#include <gtest/gtest.h>
#include <limits>

namespace mlod {
namespace {

LodLevel level(std::string name, double threshold, double ratio = 1.0, double distance = 0.0) {
  LodLevel out;
  out.name = std::move(name);
  out.motionThreshold = threshold;
  out.meshRatio = ratio;
  out.switchDistanceCm = distance;
  return out;
}

// The original and three levels with distinct ratios and increasing distances.
LodSet sampleSet() {
  LodSet lods;
  lods.levels = {level("LOD0", 0.0), level("Near", 5.0, 0.8, 500.0), level("Mid", 50.0, 0.5, 1000.0),
                 level("Far", 300.0, 0.2, 4000.0)};
  return lods;
}

std::vector<double> thresholds(const LodSet& lods) {
  std::vector<double> out;
  for (const LodLevel& l : lods.levels)
    out.push_back(l.motionThreshold);
  return out;
}

std::vector<double> distances(const LodSet& lods) {
  std::vector<double> out;
  for (const LodLevel& l : lods.levels)
    out.push_back(l.switchDistanceCm);
  return out;
}

// Guards the naming rule: LOD<count>, skipping names already taken (a renamed level may hold it).
TEST(LodLevels, NewLevelIsNamedAfterTheCountAndSkipsTakenNames) {
  LodSet lods = sampleSet();
  EXPECT_EQ(nextLodLevelName(lods), "LOD4");
  lods.levels[1].name = "LOD4";
  lods.levels[2].name = "LOD5";
  EXPECT_EQ(nextLodLevelName(lods), "LOD6");
}

// Guards the default threshold the + button offers: twice the last, 5 after the original alone.
TEST(LodLevels, NextThresholdDoublesTheLastOrStartsAtFive) {
  EXPECT_EQ(nextLodLevelThreshold(sampleSet()), 600.0);
  LodSet original;
  original.levels = {level("LOD0", 0.0)};
  EXPECT_EQ(nextLodLevelThreshold(original), 5.0);
}

// Guards add: last, the last level's ratio and distance, a new level in `order`.
TEST(LodLevels, AddAppendsWithTheLastLevelsRatioAndDistance) {
  const LodSet lods = sampleSet();
  Result<LodSetEdit> edit = addLodLevel(lods, 600.0);
  ASSERT_TRUE(edit) << edit.message();
  ASSERT_EQ(edit->lods.levels.size(), 5u);
  const LodLevel& added = edit->lods.levels.back();
  EXPECT_EQ(added.name, "LOD4");
  EXPECT_EQ(added.motionThreshold, 600.0);
  EXPECT_EQ(added.meshRatio, 0.2);
  EXPECT_EQ(added.switchDistanceCm, 4000.0);
  EXPECT_EQ(edit->order, (std::vector<int>{0, 1, 2, 3, -1}));
  EXPECT_FALSE(edit->lods.validate());
  EXPECT_EQ(lods, sampleSet()); // the input is untouched
}

// Guards the threshold rule on add and on edit: finite and >= 0.
TEST(LodLevels, ThresholdsMustBeFiniteAndNonNegative) {
  for (double bad : {-1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    EXPECT_FALSE(addLodLevel(sampleSet(), bad)) << bad;
    EXPECT_FALSE(setLodLevelThreshold(sampleSet(), 2, bad)) << bad;
  }
  Result<LodSetEdit> edit = setLodLevelThreshold(sampleSet(), 2, 70.0);
  ASSERT_TRUE(edit);
  EXPECT_EQ(thresholds(edit->lods), (std::vector<double>{0, 5, 70, 300}));
  EXPECT_EQ(edit->order, (std::vector<int>{0, 1, 2, 3}));
}

// Guards level 0: never removed, moved, or given a threshold, ratio or distance; renamed only.
TEST(LodLevels, TheOriginalIsFixedButCanBeRenamed) {
  const LodSet lods = sampleSet();
  EXPECT_FALSE(removeLodLevel(lods, 0));
  EXPECT_FALSE(moveLodLevel(lods, 0, 2));
  EXPECT_FALSE(moveLodLevel(lods, 2, 0));
  EXPECT_FALSE(setLodLevelThreshold(lods, 0, 5.0));
  EXPECT_FALSE(setLodLevelMeshRatio(lods, 0, 0.5));
  Result<LodSetEdit> distance = setLodLevelSwitchDistance(lods, 0, 10.0);
  ASSERT_FALSE(distance);
  EXPECT_NE(distance.message().find("original"), std::string::npos);
  Result<LodSetEdit> renamed = renameLodLevel(lods, 0, "Full");
  ASSERT_TRUE(renamed);
  EXPECT_EQ(renamed->lods.levels[0].name, "Full");
}

// Guards the name cap (issue 29): a rename past kMaxLevelNameBytes is refused, so no edit
// makes a project its reader would refuse.
TEST(LodLevels, OverlongNamesAreRefused) {
  const LodSet lods = sampleSet();
  EXPECT_TRUE(renameLodLevel(lods, 1, std::string(kMaxLevelNameBytes, 'n')));
  const Result<LodSetEdit> renamed = renameLodLevel(lods, 1, std::string(kMaxLevelNameBytes + 1, 'n'));
  ASSERT_FALSE(renamed);
  EXPECT_EQ(renamed.message(), "a level name has at most 256 bytes; this one has 257");
}

// Guards ranges: an index past the end is refused, not an out-of-bounds write.
TEST(LodLevels, LevelsOutOfRangeAreRefused) {
  const LodSet lods = sampleSet();
  for (int bad : {-1, 4}) {
    EXPECT_FALSE(removeLodLevel(lods, bad));
    EXPECT_FALSE(moveLodLevel(lods, bad, 1));
    EXPECT_FALSE(moveLodLevel(lods, 1, bad));
    EXPECT_FALSE(setLodLevelThreshold(lods, bad, 1.0));
    EXPECT_FALSE(renameLodLevel(lods, bad, "x"));
    EXPECT_FALSE(setLodLevelMeshRatio(lods, bad, 0.5));
    EXPECT_FALSE(setLodLevelSwitchDistance(lods, bad, 5000.0));
  }
  EXPECT_FALSE(moveLodLevel(lods, 2, 2));
}

// Guards remove: the others keep their order; `order` names where each came from.
TEST(LodLevels, RemoveKeepsTheOthersInOrder) {
  Result<LodSetEdit> edit = removeLodLevel(sampleSet(), 1);
  ASSERT_TRUE(edit);
  EXPECT_EQ(thresholds(edit->lods), (std::vector<double>{0, 50, 300}));
  EXPECT_EQ(edit->order, (std::vector<int>{0, 2, 3}));
  EXPECT_FALSE(edit->lods.validate());
}

// Guards move: the level moves with its name, threshold and ratio; the distance column stays
// with the positions, so it stays non-decreasing.
TEST(LodLevels, MoveCarriesTheLevelButNotItsDistance) {
  Result<LodSetEdit> edit = moveLodLevel(sampleSet(), 1, 3);
  ASSERT_TRUE(edit) << edit.message();
  EXPECT_EQ(thresholds(edit->lods), (std::vector<double>{0, 50, 300, 5}));
  EXPECT_EQ(edit->lods.levels[3].name, "Near");
  EXPECT_EQ(edit->lods.levels[3].meshRatio, 0.8);
  EXPECT_EQ(distances(edit->lods), (std::vector<double>{0, 500, 1000, 4000}));
  EXPECT_EQ(edit->order, (std::vector<int>{0, 2, 3, 1}));
  EXPECT_FALSE(edit->lods.validate());
}

// Guards names: non-empty after trimming, unique; the refusal says which level holds it.
TEST(LodLevels, NamesAreTrimmedNonEmptyAndUnique) {
  Result<LodSetEdit> taken = renameLodLevel(sampleSet(), 3, "Mid");
  ASSERT_FALSE(taken);
  EXPECT_NE(taken.message().find("already named"), std::string::npos) << taken.message();
  EXPECT_FALSE(renameLodLevel(sampleSet(), 3, "  \t"));
  Result<LodSetEdit> trimmed = renameLodLevel(sampleSet(), 3, "  Crowd ");
  ASSERT_TRUE(trimmed);
  EXPECT_EQ(trimmed->lods.levels[3].name, "Crowd");
  EXPECT_TRUE(renameLodLevel(sampleSet(), 2, "Mid")); // its own name again: no conflict
}

// Guards the mesh ratio rule: (0, 1].
TEST(LodLevels, MeshRatiosAreInTheHalfOpenUnitInterval) {
  for (double bad : {0.0, -0.5, 1.5, std::numeric_limits<double>::quiet_NaN()})
    EXPECT_FALSE(setLodLevelMeshRatio(sampleSet(), 2, bad)) << bad;
  Result<LodSetEdit> edit = setLodLevelMeshRatio(sampleSet(), 2, 1.0);
  ASSERT_TRUE(edit);
  EXPECT_EQ(edit->lods.levels[2].meshRatio, 1.0);
}

// Guards switch distances: at least the previous level's; later levels nearer than the new
// distance move out to it in the same edit, farther ones stay.
TEST(LodLevels, SwitchDistancesPushLaterLevelsOutward) {
  Result<LodSetEdit> nearer = setLodLevelSwitchDistance(sampleSet(), 2, 400.0);
  ASSERT_FALSE(nearer);
  EXPECT_NE(nearer.message().find("at least the previous level's"), std::string::npos) << nearer.message();
  EXPECT_FALSE(setLodLevelSwitchDistance(sampleSet(), 2, std::numeric_limits<double>::infinity()));
  Result<LodSetEdit> edit = setLodLevelSwitchDistance(sampleSet(), 1, 1500.0);
  ASSERT_TRUE(edit);
  EXPECT_EQ(distances(edit->lods), (std::vector<double>{0, 1500, 1500, 4000}));
  EXPECT_FALSE(edit->lods.validate());
  Result<LodSetEdit> closer = setLodLevelSwitchDistance(sampleSet(), 2, 600.0); // may come nearer too
  ASSERT_TRUE(closer);
  EXPECT_EQ(distances(closer->lods), (std::vector<double>{0, 500, 600, 4000}));
}

// Guards a generated set replacing the levels: overrides stay by index where a level was.
// Guards the budget a unit change regenerates from: the first level with a switch distance
// says it (1 px where it stores none); without distances there is nothing to regenerate.
TEST(LodLevels, SwitchDistancePixelBudgetIsTheFirstDistancedLevels) {
  LodSet lods = sampleSet();
  EXPECT_EQ(switchDistancePixelBudget(lods), 1.0); // distances without stored pixel errors
  lods.levels[1].pixelError = 2.5;
  lods.levels[2].pixelError = 7.0;
  EXPECT_EQ(switchDistancePixelBudget(lods), 2.5);
  lods.levels[1].switchDistanceCm = 0.0;
  EXPECT_EQ(switchDistancePixelBudget(lods), 7.0);
  for (LodLevel& l : lods.levels)
    l.switchDistanceCm = 0.0;
  EXPECT_FALSE(switchDistancePixelBudget(lods));
}

TEST(LodLevels, ReplacedLevelsKeepOverridesByIndex) {
  LodSet generated = sampleSet();
  generated.levels.push_back(level("LOD4", 500.0, 0.1, 8000.0));
  LodSet before = sampleSet();
  before.levels.pop_back();
  const LodSetEdit edit = replaceLodLevels(before, generated);
  EXPECT_EQ(edit.lods, generated);
  EXPECT_EQ(edit.order, (std::vector<int>{0, 1, 2, -1, -1}));
}

// Guards applyLodSetEdit: a joint's override follows its level when levels move or go.
TEST(LodLevels, ProjectOverridesFollowTheirLevel) {
  Project project;
  project.lods = sampleSet();
  ProjectAsset asset;
  asset.path = "a.bvh";
  asset.joints["Neck"].thresholds = {std::nullopt, 11.0, std::nullopt, 33.0};
  project.assets.push_back(asset);
  Result<LodSetEdit> moved = moveLodLevel(project.lods, 1, 2);
  ASSERT_TRUE(moved);
  applyLodSetEdit(project, *moved);
  EXPECT_EQ(project.lods, moved->lods);
  EXPECT_EQ(project.assets[0].joints["Neck"].thresholds,
            (std::vector<std::optional<double>>{std::nullopt, std::nullopt, 11.0, 33.0}));
  Result<LodSetEdit> removed = removeLodLevel(project.lods, 3);
  ASSERT_TRUE(removed);
  applyLodSetEdit(project, *removed);
  EXPECT_EQ(project.assets[0].joints["Neck"].thresholds,
            (std::vector<std::optional<double>>{std::nullopt, std::nullopt, 11.0}));
  EXPECT_FALSE(project.validate());
}

} // namespace
} // namespace mlod
