// Edits of a project's motion mappings (core/project_mappings.h): the rules the editor's
// Assets dock and mapping table keep, on the bundled CMU sample mapped onto itself.

#include "core/project_mappings.h"
#include "io/importer.h"

#include <gtest/gtest.h>
#include <stdexcept>

namespace mlod {
namespace {

const Asset& sample() {
  static const Asset asset = [] {
    Result<Asset> imported = importAsset(MLOD_SAMPLE_BVH);
    if (!imported)
      throw std::runtime_error(imported.message());
    return std::move(imported).value();
  }();
  return asset;
}

Project twoAssets() {
  Project project;
  project.assets = {ProjectAsset{"motion.bvh", 0.0, {}}, ProjectAsset{"character.bvh", 0.0, {}}};
  return project;
}

const std::vector<const Asset*> kBoth = {&sample(), &sample()};

// Guards assign: the automatic table, named for people, replacing an earlier assignment of
// the same pair and going last.
TEST(ProjectMappings, AssignUsesTheAutomaticTableAndReplacesTheSamePair) {
  Project project = twoAssets();
  Result<std::vector<ProjectMapping>> first = withMotionAssigned(project, kBoth, 0, 1, "motion.bvh", "character.bvh");
  ASSERT_TRUE(first) << first.message();
  ASSERT_EQ(first->size(), 1u);
  EXPECT_EQ((*first)[0].mapping.motionName, "motion.bvh");
  EXPECT_EQ((*first)[0].mapping.pairs.size(),
            MotionMapping::automatic(sample().skeleton, sample().skeleton).pairs.size());
  EXPECT_FALSE((*first)[0].mapping.pairs.empty());
  project.mappings = *first;
  Result<std::vector<ProjectMapping>> again = withMotionAssigned(project, kBoth, 0, 1, "m", "c");
  ASSERT_TRUE(again);
  ASSERT_EQ(again->size(), 1u);
  EXPECT_EQ((*again)[0].mapping.motionName, "m");
  EXPECT_TRUE(project.mappings[0].mapping.motionName == "motion.bvh"); // the input is untouched
}

// Guards the refusals: one asset twice, out of range, missing, a motion without a clip.
TEST(ProjectMappings, AssignRefusesWhatCannotPlay) {
  const Project project = twoAssets();
  EXPECT_FALSE(withMotionAssigned(project, kBoth, 0, 0, "m", "c"));
  EXPECT_FALSE(withMotionAssigned(project, kBoth, 0, 2, "m", "c"));
  const std::vector<const Asset*> missing = {&sample(), nullptr};
  Result<std::vector<ProjectMapping>> relink = withMotionAssigned(project, missing, 0, 1, "m", "c");
  ASSERT_FALSE(relink);
  EXPECT_NE(relink.message().find("relink"), std::string::npos);
  Asset still = sample();
  still.clips.clear();
  const std::vector<const Asset*> noClip = {&still, &sample()};
  Result<std::vector<ProjectMapping>> clipless = withMotionAssigned(project, noClip, 0, 1, "still.bvh", "c");
  ASSERT_FALSE(clipless);
  EXPECT_NE(clipless.message().find("still.bvh has no clip"), std::string::npos) << clipless.message();
}

// Guards pair edits: a pair set and a joint left at rest; unknown joints and mappings refused;
// reset brings the automatic table back; unassign removes the mapping.
TEST(ProjectMappings, PairsEditResetAndUnassign) {
  Project project = twoAssets();
  project.mappings = *withMotionAssigned(project, kBoth, 0, 1, "m", "c");
  const MotionMapping automatic = project.mappings[0].mapping;
  Result<std::vector<ProjectMapping>> cleared = withMappingPair(project, kBoth, 0, "Head", "");
  ASSERT_TRUE(cleared) << cleared.message();
  EXPECT_NE((*cleared)[0].mapping, automatic);
  EXPECT_FALSE(withMappingPair(project, kBoth, 0, "NoSuchJoint", "Head"));
  EXPECT_FALSE(withMappingPair(project, kBoth, 0, "Head", "NoSuchJoint"));
  EXPECT_FALSE(withMappingPair(project, kBoth, 3, "Head", "Head"));
  project.mappings = *cleared;
  Result<std::vector<ProjectMapping>> reset = withAutomaticMapping(project, kBoth, 0);
  ASSERT_TRUE(reset);
  EXPECT_EQ((*reset)[0].mapping, automatic);
  Result<std::vector<ProjectMapping>> gone = withoutMapping(project, 0);
  ASSERT_TRUE(gone);
  EXPECT_TRUE(gone->empty());
  EXPECT_FALSE(withoutMapping(project, 1));
}

} // namespace
} // namespace mlod
