#pragma once
// The runtime bundle (docs/architecture.md sections 2 and 8; the byte layout is docs/bundle-format.md):
// one character's LOD levels as an engine loads them, in a versioned little-endian binary
// that this file reads and writes with GLM and the standard library alone.
//
// Per level: the level's skeleton (after bone reduction: each joint's joint in the original
// skeleton, parent, inverse bind), its clips as LodClip sources (clusters per joint, local
// rotation / translation / scale tracks; inside a cluster the rotation is the key's, so
// those frames are stored once), and its skinning mesh (positions, normals, triangles, four
// joint indices and weights per vertex). readBundle() gives them back exactly: a LodClip
// built from a read clip equals the one built from the written clip, bit for bit.
//
// Reading never trusts the file: every section's size and CRC-32 are checked, every count
// against the bytes that remain, every index against what it indexes; a truncated,
// corrupt, or newer-version bundle is refused with a message that says which and where.
//
// Units: lengths in cm, time in seconds, thresholds in cm·degrees.

#include "runtime/lod_clip.h"
#include "runtime/skinning_job.h"

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace mlod {

inline constexpr char kBundleMagic[8] = {'M', 'L', 'O', 'D', 'B', 'N', 'D', 'L'};
inline constexpr std::uint32_t kBundleVersion = 1;
// The most joint-frames (frames x joints, summed over every clip of every level) a bundle
// may expand to when read: a static track takes 13 bytes in the file whatever the frame
// count, so a small file could otherwise ask for gigabytes. 2^25 = 33.5 M: e.g. 8 levels of
// a 60-joint, 10-minute clip at 120 fps (about 1.3 GB of tracks).
inline constexpr std::uint64_t kMaxBundleJointFrames = std::uint64_t(1) << 25;
// Why a bundle of `levels` levels of clips of `frames` frames in all (`joints` joints at
// the original level, 0 without a skeleton) cannot be written, or empty: checked before a
// package is built. Level 0 is the original (every joint); any other level keeps at least
// its root, so the joint-frames counted are a lower bound of what the bundle needs (a
// 1,000,000-frame clip grew past 12 GB before the writer refused it).
std::string bundlePlanProblem(std::uint64_t frames, int joints, int levels, bool withOriginal);
// The largest bundle file readBundleFile() reads (regular files only; runtime/input_file.h).
inline constexpr std::uint64_t kMaxBundleFileBytes = std::uint64_t(2) << 30;

// A clip as LodClip::build() takes it, owning its arrays.
struct BundleClip {
  std::string name;
  double fps = 30.0;
  std::int32_t frameCount = 0;
  std::int32_t jointCount = 0;
  bool looping = false;
  std::vector<glm::quat> rotations; // [joint * frameCount + frame]
  std::vector<glm::vec3> translations;
  std::vector<glm::vec3> scales;
  std::vector<LodCluster> clusters;          // joint after joint
  std::vector<std::uint32_t> clusterBegin;   // jointCount + 1 entries, or none

  LodClipSource source() const;
  // The clip for `blendFrames` frames of unfreeze blending (LodClipSource::blendFrames).
  std::optional<LodClip> build(std::string* out_error = nullptr, int blendFrames = 0) const {
    LodClipSource built = source();
    built.blendFrames = blendFrames;
    return LodClip::build(built, out_error);
  }
};

// A level's skinning mesh, bound to the level's skeleton.
struct BundleMesh {
  std::vector<glm::vec3> positions; // cm, bind pose
  std::vector<glm::vec3> normals;   // one per vertex, or none
  std::vector<std::uint32_t> indices; // triangles
  std::vector<glm::u16vec4> joints;   // per vertex, sorted by weight (largest first), unused slots weight 0
  std::vector<glm::vec4> weights;

  std::optional<SkinningMesh> build(int jointCount, std::string* out_error = nullptr) const {
    return SkinningMesh::build(positions, normals, joints, weights, jointCount, out_error);
  }
};

struct BundleLevel {
  std::int32_t index = 0; // the level's index in the LOD set it came from
  std::string name;
  double motionThreshold = 0.0; // cm·degrees
  double meshRatio = 1.0;
  double switchDistanceCm = 0.0;
  double pixelError = 0.0;
  double screenSizePixels = 0.0;
  double motionErrorCm = 0.0;
  double meshErrorCm = 0.0;
  // The level's skeleton: per joint, its joint in the bundle's skeleton, its parent (in
  // this level, -1 for the root) and its inverse bind (palette = model x inverse bind).
  std::vector<std::int32_t> fullJoints;
  std::vector<std::int16_t> parents;
  std::vector<glm::mat4> inverseBinds;
  std::vector<BundleClip> clips; // each of the level's joint count
  std::optional<BundleMesh> mesh;

  int jointCount() const { return static_cast<int>(parents.size()); }
};

struct Bundle {
  std::string name;       // the character
  std::string source;     // the file it was exported from
  double verticalFovDegrees = 60.0; // the projection the pixel figures assume
  double viewportHeightPixels = 1080.0;
  double boundingRadiusCm = 0.0;
  std::vector<std::string> jointNames; // the original skeleton
  std::vector<std::int16_t> jointParents;
  std::vector<BundleLevel> levels;
};

// What an engine plays, built from a read bundle level.
struct BundleLevelRuntime {
  std::vector<LodClip> clips;
  std::optional<SkinningMesh> mesh;
};

// The bundle's bytes. The bundle must be consistent (validateBundle()); an inconsistent one
// gives an empty vector and the reason.
std::vector<std::uint8_t> writeBundle(const Bundle& bundle, std::string* out_error = nullptr);

// Reads a bundle; nothing and the reason on any error (never reads out of bounds).
std::optional<Bundle> readBundle(std::span<const std::uint8_t> bytes, std::string* out_error = nullptr);
// readBundleFile() reads regular files of at most kMaxBundleFileBytes only (a FIFO or a
// device is refused before it is opened).
std::optional<Bundle> readBundleFile(const std::string& path, std::string* out_error = nullptr);

// The rules a bundle keeps (both writeBundle() and readBundle() check them): a name; at
// least one level and at most 65,535; original joints 1..32,767 with parents before
// children; per level, joints with a valid full joint each, parents before children,
// finite affine inverse binds, clips whose joint count is the level's, a mesh whose indices
// and joints are in range. Empty string when fine.
std::string validateBundle(const Bundle& bundle);

// The level's LodClips, for `blendFrames` frames of unfreeze blending (the N the engine
// plays them with: LodClipSource::blendFrames), and SkinningMesh. Errors: what
// LodClip::build() and SkinningMesh::build() refuse.
std::optional<BundleLevelRuntime> buildBundleLevel(const BundleLevel& level, std::string* out_error = nullptr,
                                                   int blendFrames = 0);

// CRC-32 (IEEE 802.3, as zlib's crc32()).
std::uint32_t crc32(std::span<const std::uint8_t> bytes);

} // namespace mlod
