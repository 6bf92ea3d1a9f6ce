// Edits of per-joint JPC settings (core/jpc/joint_settings_edits.h): the Skeleton dock's
// rules, checked without the editor.

#include "core/jpc/joint_settings_edits.h"
#include "unit/core/fixtures.h"

#include <gtest/gtest.h>
#include <limits>

namespace mlod {
namespace {

const std::vector<std::string> kNeck = {"Neck"};

// Guards tidy: an entry that says nothing goes, trailing absent overrides go with it.
TEST(JointSettingsEdits, TidyDropsEntriesThatSayNothing) {
  JointSettingsMap joints;
  joints["A"].thresholds = {std::nullopt, 3.0, std::nullopt};
  joints["B"].thresholds = {std::nullopt, std::nullopt};
  joints["C"].locked = true;
  tidyJointSettings(joints);
  EXPECT_EQ(joints.size(), 2u);
  EXPECT_EQ(joints["A"].thresholds.size(), 2u);
  EXPECT_FALSE(joints.count("B"));
}

// Guards a cleared override: back to the defaults, the entry is gone (equal settings compare equal).
TEST(JointSettingsEdits, ClearingAnOverrideRemovesTheEntry) {
  Result<JointSettingsMap> set = withJointThreshold({}, kNeck, 2, 11.0);
  ASSERT_TRUE(set);
  EXPECT_EQ(*set->at("Neck").thresholds[2], 11.0);
  Result<JointSettingsMap> cleared = withJointThreshold(*set, kNeck, 2, std::nullopt);
  ASSERT_TRUE(cleared);
  EXPECT_TRUE(cleared->empty());
}

// Guards the rules: level 0 has nothing to override; alpha and thresholds finite and >= 0.
TEST(JointSettingsEdits, BadValuesAndTheOriginalLevelAreRefused) {
  EXPECT_FALSE(withJointThreshold({}, kNeck, 0, 5.0));
  EXPECT_FALSE(withJointThreshold({}, kNeck, 1, -5.0));
  EXPECT_FALSE(withJointAlpha({}, kNeck, std::numeric_limits<double>::quiet_NaN()));
  EXPECT_FALSE(withJointAlpha({}, kNeck, -1.0));
  Result<JointSettingsMap> alpha = withJointAlpha({}, kNeck, 0.0);
  ASSERT_TRUE(alpha);
  EXPECT_EQ(*alpha->at("Neck").alpha, 0.0);
}

// Guards locks: set and cleared, several joints at once.
TEST(JointSettingsEdits, LocksSeveralJoints) {
  const std::vector<std::string> names = {"a", "b"};
  const JointSettingsMap locked = withJointsLocked({}, names, true);
  EXPECT_TRUE(locked.at("a").locked && locked.at("b").locked);
  EXPECT_TRUE(withJointsLocked(locked, names, false).empty());
}

// Guards mesh importance: set on several joints, refused unless finite and > 0, and an entry
// back at importance 1 with nothing else to say is tidied away.
TEST(JointSettingsEdits, MeshImportanceIsCheckedAndTidied) {
  const std::vector<std::string> names = {"Head", "Neck"};
  const Result<JointSettingsMap> raised = withJointMeshImportance({}, names, 4.0);
  ASSERT_TRUE(raised);
  EXPECT_EQ(raised->at("Head").meshImportance, 4.0);
  EXPECT_EQ(raised->at("Neck").meshImportance, 4.0);
  EXPECT_FALSE(withJointMeshImportance({}, names, 0.0));
  EXPECT_FALSE(withJointMeshImportance({}, names, -1.0));
  EXPECT_FALSE(withJointMeshImportance({}, names, std::numeric_limits<double>::infinity()));
  const Result<JointSettingsMap> back = withJointMeshImportance(*raised, kNeck, 1.0);
  ASSERT_TRUE(back);
  EXPECT_EQ(back->size(), 1u);
  EXPECT_EQ(back->at("Head").meshImportance, 4.0);
}

// Guards apply-to-children: every descendant (not only children) takes the joint's settings,
// a joint without settings clears them, other branches stay.
TEST(JointSettingsEdits, SettingsGoToEveryDescendant) {
  const Skeleton chain = test::makeChain(4); // j0 -> j1 -> j2 -> j3
  JointSettingsMap joints;
  joints["j1"].alpha = 2.0;
  joints["j3"].locked = true;
  joints["j0"].thresholds = {std::nullopt, 4.0};
  const JointSettingsMap out = withSettingsOnDescendants(joints, chain, 1);
  EXPECT_EQ(*out.at("j2").alpha, 2.0);
  EXPECT_EQ(*out.at("j3").alpha, 2.0);
  EXPECT_FALSE(out.at("j3").locked);
  EXPECT_EQ(out.at("j0"), joints.at("j0"));
  EXPECT_EQ(withSettingsOnDescendants(joints, chain, 2).count("j3"), 0u); // j2 has none: j3's go
}

} // namespace
} // namespace mlod
