// MotionMapping (docs/architecture.md section 3; Ahn & Wohn, section 3.1): rig-convention name matching,
// the editable table, the committed CMU 01_01 -> BCN_Epileptic mapping and the motion played
// on the character through rest-pose difference matrices.

#include "core/mapping/joint_names.h"
#include "core/mapping/motion_mapping.h"
#include "unit/core/mesh_lod_fixtures.h"

#include <gtest/gtest.h>

#include <fstream>
#include <iostream>
#include <sstream>

namespace mlod {
namespace {

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

MotionMapping committedMapping() {
  Result<MotionMapping> mapping =
      motionMappingFromJson(readFile(std::string(MLOD_TEST_DATA_DIR) + "/mappings/cmu_01_01_to_bcn_epileptic.json"));
  if (!mapping)
    throw std::runtime_error(mapping.message());
  return std::move(mapping).value();
}

const Asset& cmu() { return test::meshAsset("BVH/01_01.bvh"); }
const Asset& bcn() { return test::bcnEpileptic(); }

struct RoleCase {
  const char* name;
  const char* part;
  BodySide side;
};

TEST(JointNames, CommonRigConventionsGiveTheSameRoles) {
  const RoleCase cases[] = {
      // CMU / MotionBuilder
      {"Hips", "hips", BodySide::Center},
      {"LHipJoint", "hip_side", BodySide::Left},
      {"LeftUpLeg", "thigh", BodySide::Left},
      {"RightLeg", "shin", BodySide::Right},
      {"LeftFoot", "foot", BodySide::Left},
      {"RightToeBase", "toe", BodySide::Right},
      {"LowerBack", "spine", BodySide::Center},
      {"Neck1", "neck", BodySide::Center},
      {"LeftShoulder", "clavicle", BodySide::Left},
      {"RightArm", "upper_arm", BodySide::Right},
      {"LeftForeArm", "forearm", BodySide::Left},
      {"RightHand", "hand", BodySide::Right},
      {"LThumb", "thumb", BodySide::Left},
      {"RFingers", "finger", BodySide::Right},
      // Mixamo
      {"mixamorig:Hips", "hips", BodySide::Center},
      {"mixamorig:Spine2", "spine", BodySide::Center},
      {"mixamorig:LeftHandThumb1", "thumb", BodySide::Left},
      {"mixamorig:RightUpLeg", "thigh", BodySide::Right},
      {"mixamorig:LeftForeArm", "forearm", BodySide::Left},
      // B_ style (BCN_Epileptic)
      {"B_Root_Pelvis_L", "hips", BodySide::Center},
      {"B_Hip_Left", "thigh", BodySide::Left},
      {"B_Knee_Right", "shin", BodySide::Right},
      {"B_Ankle_Left", "foot", BodySide::Left},
      {"B_Clavicle_Right", "clavicle", BodySide::Right},
      {"B_UpperArm_Left", "upper_arm", BodySide::Left},
      {"B_Finger2_Left", "finger", BodySide::Left},
      {"B_UpperEyeLid_Left", "eyelid", BodySide::Left},
      {"B_EyeBrow_Right", "brow", BodySide::Right},
      {"B_Jaw", "jaw", BodySide::Center},
      // 3ds Max Biped, Unreal, Blender
      {"Bip01 L Thigh", "thigh", BodySide::Left},
      {"Bip01 R Calf", "shin", BodySide::Right},
      {"Bip01 Spine1", "spine", BodySide::Center},
      {"thigh_l", "thigh", BodySide::Left},
      {"lowerarm_r", "forearm", BodySide::Right},
      {"ball_l", "toe", BodySide::Left},
      {"hand.L", "hand", BodySide::Left},
      {"upper_arm.R", "upper_arm", BodySide::Right},
  };
  for (const RoleCase& c : cases) {
    const JointRole role = jointRole(c.name);
    EXPECT_EQ(role.part, c.part) << c.name;
    EXPECT_EQ(role.side, c.side) << c.name;
  }
  EXPECT_EQ(jointRole("B_Spine3").number, 3);
  EXPECT_EQ(jointRole("Bip01 Spine1").number, 1) << "Bip01 is the rig's name, not a number";
  EXPECT_TRUE(jointRole("EndSite_LFingers").end);
  EXPECT_TRUE(jointRole("mixamorig:HeadTop_End").end);
  EXPECT_EQ(nameTokens("LeftUpLeg"), (std::vector<std::string>{"left", "up", "leg"}));
  EXPECT_EQ(nameTokens("mixamorig:LeftHandThumb1"), (std::vector<std::string>{"left", "hand", "thumb", "1"}));
}

TEST(MotionMapping, AutomaticMatchOfCmuOnBcnAgreesWithTheCommittedMapping) {
  const MotionMapping automatic = MotionMapping::automatic(cmu().skeleton, bcn().skeleton);
  ASSERT_FALSE(automatic.validate(cmu().skeleton, bcn().skeleton));
  const MotionMapping reference = committedMapping();
  const MappingAgreement agreement = compareMappings(automatic, reference);
  std::cout << "[ hit rate ] automatic CMU 01_01 -> BCN_Epileptic: " << agreement.found << " of "
            << agreement.referencePairs << " committed pairs (" << agreement.hitRatePercent() << "%), "
            << agreement.wrong << " mapped differently, " << agreement.missing << " left out, " << agreement.extra
            << " extra" << std::endl;
  RecordProperty("hit_rate_percent", std::to_string(agreement.hitRatePercent()));
  EXPECT_EQ(agreement.referencePairs, 27);
  EXPECT_GE(agreement.hitRatePercent(), 80.0);
  // the limbs, the place where a wrong guess costs most, all match
  for (const char* joint : {"B_Hip_Left", "B_Knee_Left", "B_Ankle_Left", "B_Toe_Left", "B_Hip_Right", "B_Knee_Right",
                            "B_Clavicle_Left", "B_UpperArm_Left", "B_ForeArm_Left", "B_Hand_Left", "B_UpperArm_Right",
                            "B_ForeArm_Right", "B_Hand_Right", "B_Root_Pelvis_L"}) {
    ASSERT_NE(automatic.motionFor(joint), nullptr) << joint;
    EXPECT_EQ(*automatic.motionFor(joint), *reference.motionFor(joint)) << joint;
  }
}

TEST(MotionMapping, AutomaticMatchOfASkeletonWithItselfIsTheIdentity) {
  const Skeleton& skeleton = cmu().skeleton;
  const MotionMapping mapping = MotionMapping::automatic(skeleton, skeleton);
  int named = 0;
  for (const Joint& joint : skeleton.joints) {
    const JointRole role = jointRole(joint.name);
    if (role.part.empty() || role.end)
      continue;
    ++named;
    ASSERT_NE(mapping.motionFor(joint.name), nullptr) << joint.name;
    EXPECT_EQ(*mapping.motionFor(joint.name), joint.name);
  }
  EXPECT_EQ(int(mapping.pairs.size()), named);
  EXPECT_EQ(named, 31); // every joint with a rotation channel
}

TEST(MotionMapping, TheTableIsEditableAndValidated) {
  MotionMapping mapping = committedMapping();
  ASSERT_FALSE(mapping.validate(cmu().skeleton, bcn().skeleton));
  // set() replaces whatever held either joint
  mapping.set("B_Spine2", "Spine");
  EXPECT_EQ(*mapping.motionFor("B_Spine2"), "Spine");
  EXPECT_EQ(mapping.motionFor("B_Spine3"), nullptr);
  mapping.clear("B_Spine2");
  EXPECT_EQ(mapping.motionFor("B_Spine2"), nullptr);
  EXPECT_FALSE(mapping.validate(cmu().skeleton, bcn().skeleton));
  // unknown names and joints used twice are errors
  MotionMapping bad = mapping;
  bad.pairs.push_back({"B_NoSuchJoint", "Spine"});
  EXPECT_TRUE(bad.validate(cmu().skeleton, bcn().skeleton));
  bad = mapping;
  bad.pairs.push_back({"B_Spine2", "LeftUpLeg"});
  EXPECT_TRUE(bad.validate(cmu().skeleton, bcn().skeleton)) << "LeftUpLeg drives two joints";
  bad = mapping;
  bad.pairs.push_back({"B_Hip_Left", "Spine"});
  EXPECT_TRUE(bad.validate(cmu().skeleton, bcn().skeleton)) << "B_Hip_Left mapped twice";
}

TEST(MotionMapping, JsonRoundTripsAndRejectsWhatIsNotAMapping) {
  const MotionMapping mapping = committedMapping();
  Result<MotionMapping> back = motionMappingFromJson(motionMappingToJson(mapping));
  ASSERT_TRUE(back) << back.message();
  EXPECT_EQ(*back, mapping);
  EXPECT_FALSE(motionMappingFromJson("not json"));
  EXPECT_FALSE(motionMappingFromJson(R"({"format":"motionlod-project","version":1})"));
  EXPECT_FALSE(motionMappingFromJson(R"({"format":"motionlod-mapping","version":99,"pairs":[]})"));
  EXPECT_FALSE(motionMappingFromJson(R"({"format":"motionlod-mapping","version":1,"pairs":[{"character":1}]})"));
}

class Retarget : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    Result<RestPoseDifferences> differences =
        restPoseDifferences(committedMapping(), cmu().skeleton, bcn().skeleton);
    ASSERT_TRUE(differences) << differences.message();
    s_differences = new RestPoseDifferences(std::move(differences).value());
    Result<Clip> clip = retargetClip(*s_differences, cmu().skeleton, cmu().clips.at(0), bcn().skeleton);
    ASSERT_TRUE(clip) << clip.message();
    s_clip = new Clip(std::move(clip).value());
  }
  static void TearDownTestSuite() {
    delete s_differences;
    delete s_clip;
  }
  static RestPoseDifferences* s_differences;
  static Clip* s_clip;
};
RestPoseDifferences* Retarget::s_differences = nullptr;
Clip* Retarget::s_clip = nullptr;

TEST_F(Retarget, TheCmuClipPlaysOnBcnAsAValidClip) {
  const Clip& source = cmu().clips.at(0);
  EXPECT_FALSE(s_clip->validate(bcn().skeleton)) << s_clip->validate(bcn().skeleton).message();
  EXPECT_EQ(s_clip->frameCount, source.frameCount);
  EXPECT_EQ(s_clip->fps, source.fps);
  EXPECT_EQ(s_clip->rotationChannelCount(), 27); // the mapped joints (the root among them)
  // both skeletons are Y-up and face +z: no axis change
  EXPECT_NEAR(std::abs(s_differences->alignment.w), 1.0, 1e-9);
  // BCN is about twice the size of CMU subject 01 at 5.6444 cm per unit
  EXPECT_GT(s_differences->scale, 1.0);
  EXPECT_LT(s_differences->scale, 3.0);
}

TEST_F(Retarget, WhereAMotionBonePointsTheCharactersBonePoints) {
  // the rest-pose difference matrices carry directions: for bones that are one parent-child
  // step in both skeletons, the character's bone is parallel to the motion's (after A)
  const std::pair<const char*, const char*> bones[][2] = {
      {{"B_UpperArm_Left", "B_ForeArm_Left"}, {"LeftArm", "LeftForeArm"}},
      {{"B_ForeArm_Left", "B_Hand_Left"}, {"LeftForeArm", "LeftHand"}},
      {{"B_UpperArm_Right", "B_ForeArm_Right"}, {"RightArm", "RightForeArm"}},
      {{"B_Hip_Left", "B_Knee_Left"}, {"LeftUpLeg", "LeftLeg"}},
      {{"B_Knee_Left", "B_Ankle_Left"}, {"LeftLeg", "LeftFoot"}},
      {{"B_Knee_Right", "B_Ankle_Right"}, {"RightLeg", "RightFoot"}},
      {{"B_Ankle_Right", "B_Toe_Right"}, {"RightFoot", "RightToeBase"}},
  };
  const Skeleton& character = bcn().skeleton;
  const Skeleton& motion = cmu().skeleton;
  const Clip& source = cmu().clips.at(0);
  std::vector<glm::mat4> cm, mm;
  double worst = 0.0;
  for (int t = 0; t < source.frameCount; t += 97) {
    s_clip->modelMatrices(character, t, cm);
    source.modelMatrices(motion, t, mm);
    for (const auto& bone : bones) {
      const glm::dvec3 c = glm::dvec3(cm[std::size_t(character.find(bone[0].second))][3]) -
                           glm::dvec3(cm[std::size_t(character.find(bone[0].first))][3]);
      const glm::dvec3 m = s_differences->alignment * (glm::dvec3(mm[std::size_t(motion.find(bone[1].second))][3]) -
                                                       glm::dvec3(mm[std::size_t(motion.find(bone[1].first))][3]));
      const double angle = std::atan2(glm::length(glm::cross(c, m)), glm::dot(c, m));
      worst = std::max(worst, angle);
      EXPECT_LT(angle, 1e-3) << bone[0].first << " at frame " << t;
    }
  }
  EXPECT_LT(worst, 1e-3);
}

TEST_F(Retarget, TheRootMovesByTheMotionsDisplacementScaled) {
  const Clip& source = cmu().clips.at(0);
  std::vector<glm::mat4> mm;
  source.modelMatrices(cmu().skeleton, 0, mm);
  const glm::dvec3 start(mm[0][3]);
  for (int t : {0, 500, 1500, source.frameCount - 1}) {
    source.modelMatrices(cmu().skeleton, t, mm);
    const glm::dvec3 expected = glm::dvec3(bcn().skeleton.joints[0].rest.translation) +
                                s_differences->alignment * ((glm::dvec3(mm[0][3]) - start) * s_differences->scale);
    const glm::dvec3 got(s_clip->translation(0, t));
    EXPECT_LT(glm::length(got - expected), 1e-3) << "frame " << t;
  }
}

TEST_F(Retarget, UnmappedJointsHoldTheirRestPose) {
  const Skeleton& character = bcn().skeleton;
  for (const char* joint : {"B_Spine2", "B_Jaw", "B_LowerPelvis", "B_Finger2_Left"}) {
    const int j = character.find(joint);
    ASSERT_GE(j, 0);
    EXPECT_EQ(s_clip->hasRotation[std::size_t(j)], 0) << joint;
    // exactly: a round trip through model space would leave float noise that keeps bone
    // reduction at threshold 0 from removing the joint
    for (int t : {0, 1000, 2000})
      EXPECT_EQ(s_clip->rotation(j, t), character.joints[std::size_t(j)].rest.rotation) << joint;
  }
}

TEST(MotionMapping, BadMappingsAreErrors) {
  MotionMapping empty;
  EXPECT_FALSE(restPoseDifferences(empty, cmu().skeleton, bcn().skeleton));
  MotionMapping unknown;
  unknown.pairs.push_back({"B_Hip_Left", "NoSuchJoint"});
  Result<RestPoseDifferences> result = restPoseDifferences(unknown, cmu().skeleton, bcn().skeleton);
  ASSERT_FALSE(result);
  EXPECT_NE(result.message().find("NoSuchJoint"), std::string::npos);
  // differences made for another character
  Result<RestPoseDifferences> ok = restPoseDifferences(committedMapping(), cmu().skeleton, bcn().skeleton);
  ASSERT_TRUE(ok);
  const test::Tube tube = test::makeTube(5, 8);
  EXPECT_FALSE(retargetClip(*ok, cmu().skeleton, cmu().clips.at(0), tube.skeleton));
}

} // namespace
} // namespace mlod
