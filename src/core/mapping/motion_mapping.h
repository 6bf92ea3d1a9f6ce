#pragma once
// A motion's joints mapped onto a character's, and the motion played on the character
// (docs/architecture.md section 3; Ahn & Wohn, section 3.1: "During the preprocessing, current
// animation system aligns the selected motion / character structure and calculates
// difference matrix between them. At the run-time, the system transforms the joint posture
// from the motion database and applies the difference matrix.").
//
// The mapping is a table of (character joint, motion joint) pairs by name, each joint at
// most once on its side. It starts from automatic name matching (joint_names.h: body part,
// side, chains matched in order along the chain) and is then edited like any table; it is
// saved as JSON next to a project (tests/data/mappings/ holds one for CMU 01_01 on
// BCN_Epileptic).
//
// Playing a motion on a character (retargetClip): rotations are carried in model space.
// For a mapped character joint c driven by motion joint s,
//     G_c(t) = A · G_s(t) · D_c,      D_c = (A · G_s^rest)^-1 · R_c · G_c^rest
// G are model-space rotations, A aligns the motion's model axes with the character's (the
// axis-aligned rotation that best overlays the two rest poses), and R_c is the rotation that
// turns the character's rest bones at c (towards its first mapped descendants) onto the
// motion's rest bones: the "structures are aligned" first, so a T-pose motion drives an
// arms-down character correctly. D_c is the paper's difference matrix. Where a motion
// bone points, the character's bone points. Unmapped character joints keep their rest
// rotation relative to their parent; the root moves by the motion root's displacement from
// its first frame, scaled by the ratio of the two skeletons' mapped bone lengths. Lengths
// in cm; the character keeps its own bone lengths.

#include "core/clip.h"
#include "core/error.h"
#include "core/skeleton.h"

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace mlod {

struct JointPair {
  std::string character; // joint of the character's skeleton
  std::string motion;    // joint of the motion's skeleton that drives it
  friend bool operator==(const JointPair&, const JointPair&) = default;
};

class MotionMapping {
public:
  std::string motionName;    // what the motion is (a file name), for people
  std::string characterName; // what the character is
  std::vector<JointPair> pairs;

  // Automatic name matching of every joint of `character` against `motion` (joint_names.h):
  // equal body part and side; chain parts (spine, neck, fingers, tail) in order along their
  // chain, spread evenly where the two chains differ in length; where several joints claim
  // a part, the one nearest the root. End effectors are not mapped.
  static MotionMapping automatic(const Skeleton& motion, const Skeleton& character);

  // The motion joint that drives `character` joint, or nullptr.
  const std::string* motionFor(std::string_view characterJoint) const;
  // Table edits: set() replaces any pair that held either joint; clear() drops the pair of
  // a character joint (it keeps its rest pose then).
  void set(const std::string& characterJoint, const std::string& motionJoint);
  void clear(std::string_view characterJoint);

  // Rules: every name exists in its skeleton; no joint appears twice on its side.
  Error validate(const Skeleton& motion, const Skeleton& character) const;

  friend bool operator==(const MotionMapping&, const MotionMapping&) = default;
};

// Version 1: {"format":"motionlod-mapping","version":1,"motion","character",
//             "pairs":[{"character","motion"}]}
inline constexpr int kMotionMappingVersion = 1;
std::string motionMappingToJson(const MotionMapping& mapping, int indent = 2);
// Errors: not JSON, another format, a newer version, missing or mistyped fields.
Result<MotionMapping> motionMappingFromJson(std::string_view text);

// How well an automatic mapping reproduces a reference one (a committed, checked table).
struct MappingAgreement {
  int referencePairs = 0; // pairs in the reference
  int found = 0;          // reference pairs the automatic mapping has exactly
  int wrong = 0;          // character joints both map, to different motion joints
  int missing = 0;        // reference pairs whose character joint the automatic one leaves out
  int extra = 0;          // automatic pairs for character joints the reference leaves out
  double hitRatePercent() const { return referencePairs > 0 ? 100.0 * found / referencePairs : 0.0; }
};
MappingAgreement compareMappings(const MotionMapping& automatic, const MotionMapping& reference);

// What the paper's preprocessing computes once per (motion skeleton, character) pair.
struct RestPoseDifferences {
  glm::dquat alignment{1.0, 0.0, 0.0, 0.0}; // A: motion model space -> character model space
  double scale = 1.0;                       // character length / motion length
  std::vector<int> source;                  // per character joint: its motion joint, -1 = none
  std::vector<glm::dquat> difference;       // per character joint: D_c (identity where unmapped)
  int rootSource = 0;                       // motion joint whose displacement moves the character's root
};

// Errors: a mapping that does not validate against the two skeletons, an empty mapping.
Result<RestPoseDifferences> restPoseDifferences(const MotionMapping& mapping, const Skeleton& motion,
                                                const Skeleton& character);

// `clip` (of `motion`) played on `character`: a clip with the character's joints, the same
// frames and rate. Mapped joints (and the root) carry rotation channels, the root a
// translation channel; unmapped joints hold their rest pose without channels.
Result<Clip> retargetClip(const RestPoseDifferences& differences, const Skeleton& motion, const Clip& clip,
                          const Skeleton& character);

// How much of a character a mapping drives: of the character's joints that have a child
// (end effectors, face and finger tips, are what no motion maps), those the mapping names.
struct MappingCoverage {
  int mapped = 0; // joints with a child that the mapping drives
  int joints = 0; // joints with a child
  double share() const { return joints > 0 ? double(mapped) / double(joints) : 0.0; }
};
MappingCoverage mappingCoverage(const MotionMapping& mapping, const Skeleton& character);

// Below this share of MappingCoverage a motion hardly fits the character (a motion of
// another rig: most of the body would stand in its rest pose). Onto BCN_Epileptic the
// automatic mapping of CMU 01_01 or 01_03 drives 24 of its 33 joints with a child (73%), the
// checked table of tests/data/mappings 25 (76%), Boxing_Toes 15 (45%); onto Testwuson, CMU
// 01_03 drives 7 of 30 (23%). `export --motion` refuses less unless told.
inline constexpr double kMinMappedShare = 0.5;
// Whether a mapping drives less than kMinMappedShare of its character.
inline bool drivesTooLittle(const MappingCoverage& coverage) {
  return coverage.share() < kMinMappedShare;
}
// What a mapping drives, in words: "7 of Testwuson's 30 joints with a child (23%)".
std::string mappingReach(const MappingCoverage& coverage, std::string_view characterName);
// Why a mapping that drivesTooLittle() hardly fits (the CLI's refusal and the studio's warning
// say the same): "the automatic mapping drives <mappingReach()>, below 50%: the rest of the
// body would hold its rest pose".
std::string tooLittleMappedReason(const MappingCoverage& coverage, std::string_view characterName);

// A motion played on a character through the automatic mapping: what
// `motionlod bench-crowd --scene --motion` and `motionlod export --motion` do.
struct MappedMotion {
  MotionMapping mapping;   // MotionMapping::automatic(motion, character)
  std::vector<Clip> clips; // each of `clips` retargeted onto the character, in order
  MappingCoverage coverage;
};
// Errors, worded to follow the motion's file name ("error: MOTION: reason"): no clip or no
// skeleton, a mapping that finds no pair or does not fit the skeletons (restPoseDifferences(),
// naming `characterName`), a clip that is not of `motion` (retargetClip()).
Result<MappedMotion> mapMotionAutomatically(const Skeleton& motion, std::span<const Clip> clips,
                                            const Skeleton& character, std::string_view characterName);

} // namespace mlod
