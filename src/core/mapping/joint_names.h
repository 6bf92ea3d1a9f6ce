#pragma once
// What a joint's name says about its place in a humanoid rig, across the common naming
// conventions, for automatic motion-to-character mapping (motion_mapping.h):
//   CMU / MotionBuilder  Hips, LHipJoint, LeftUpLeg, LeftLeg, LeftFoot, LeftToeBase,
//                        LowerBack, Spine1, Neck1, Head, LeftShoulder, LeftArm, LeftForeArm,
//                        LeftHand, LeftFingerBase, LFingers, LThumb, EndSite_Head
//   Mixamo               mixamorig:Hips, mixamorig:Spine2, mixamorig:LeftHandThumb1,
//                        mixamorig:HeadTop_End
//   B_ style (BCN)       B_Root_Pelvis_L, B_Hip_Left, B_Knee_Left, B_Ankle_Left, B_Spine3,
//                        B_Clavicle_Left, B_UpperArm_Left, B_Finger2_Left, B_Neck, B_Jaw
//   3ds Max Biped        Bip01 L Thigh, Bip01 L Calf, Bip01 Spine1, Bip01 R Forearm
//   Unreal / others      thigh_l, calf_r, lowerarm_l, spine_02, pelvis, ball_r, hand.L
// Sides: a token "left"/"l" or "right"/"r" anywhere (prefix, suffix, separated or camel-
// cased: LThumb, L_Hand, hand.L, thigh_l, Left_Foot, B_Hip_Left). Joints on the centre line
// (hips, spine, neck, head, jaw) ignore a side token (BCN's B_Root_Pelvis_L is the pelvis).

#include <string>
#include <string_view>
#include <vector>

namespace mlod {

enum class BodySide { Center, Left, Right };

struct JointRole {
  // The body part, one of: hips, hip_side (CMU's LHipJoint), thigh, shin, foot, toe,
  // spine, neck, head, clavicle, upper_arm, forearm, hand, thumb, index, middle, ring,
  // pinky, finger, jaw, eye, eyelid, brow, lip, mouth, cheek, tongue, tail; empty when the
  // name says none of them.
  std::string part;
  BodySide side = BodySide::Center;
  int number = -1;  // a number in the name (Spine2 -> 2, Thumb1 -> 1), -1 without
  bool end = false; // an end effector by name (End Site, _End, Nub, Tip)

  // Parts that come as chains of joints (spine, neck, fingers, tail): matched by their
  // order along the chain, not by number.
  bool chain() const;
};

// The name split into lower-case words: namespace prefixes ("mixamorig:") dropped, split at
// separators, case changes and digits ("LeftUpLeg" -> left up leg; "B_Spine3" -> b spine 3).
std::vector<std::string> nameTokens(std::string_view name);

// The role a joint's name gives it.
JointRole jointRole(std::string_view name);

const char* toString(BodySide side); // "center", "left", "right"

} // namespace mlod
