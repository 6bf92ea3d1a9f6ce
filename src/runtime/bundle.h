#pragma once
// The runtime bundle (docs/architecture.md sections 2 and 8; the byte layout is docs/bundle-format.md):
// one character's LOD levels as an engine loads them, in a versioned little-endian binary
// that this file reads and writes with GLM and the standard library alone.
//
// Per level: the level's skeleton (after bone reduction: each joint's joint in the original
// skeleton, parent, inverse bind), its clips as the runtime plays them (LodClip's
// compressed storage: regions, quantized streams, static values; built for one number of
// blend frames and one precision, which each clip states), and its skinning mesh
// (positions, normals, triangles, four joint indices and weights per vertex). readBundle()
// gives them back exactly: a read clip equals the written one, bit for bit, and costs its
// bytes in the file (format version 2; version 1 stored clip sources and is refused with a
// message that says to export again).
//
// Reading never trusts the file: every section's size and CRC-32 are checked, every count
// against the bytes that remain, every index against what it indexes, and every clip's
// storage against the rules the evaluator reads it by (LodClip::storageProblem()); a
// truncated, corrupt, older- or newer-version bundle is refused with a message that says
// which and where.
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
inline constexpr std::uint32_t kBundleVersion = 2;
// The unfreeze blending an exporter builds a bundle's clips for unless told otherwise
// (frames; the bundle plugin's blend_frames option, bench-crowd's --blend-frames default).
inline constexpr int kDefaultBundleBlendFrames = 4;
// The most joint-frames (frames x joints, summed over every clip of every level) a bundle
// may hold: what an exporter builds in memory before it compresses (the clips' tracks, about
// 40 bytes a joint-frame). 2^25 = 33.5 M: e.g. 8 levels of a 60-joint, 10-minute clip at
// 120 fps (about 1.3 GB of tracks).
inline constexpr std::uint64_t kMaxBundleJointFrames = std::uint64_t(1) << 25;
// Why a bundle of `levels` levels of clips of `frames` frames in all (`joints` joints at
// the original level, 0 without a skeleton) cannot be written, or empty: checked before a
// package is built. Level 0 is the original (every joint); any other level keeps at least
// its root, so the joint-frames counted are a lower bound of what the bundle needs (a
// 1,000,000-frame clip grew past 12 GB before the writer refused it).
std::string bundlePlanProblem(std::uint64_t frames, int joints, int levels, bool withOriginal);
// The largest bundle file readBundleFile() reads (regular files only; runtime/input_file.h).
inline constexpr std::uint64_t kMaxBundleFileBytes = std::uint64_t(2) << 30;

// A clip of a level as the runtime plays it: the compressed LodClip itself (built for the
// bundle's blend frames and precision, LodClip::blendFrames() and precisionCm()), so that
// what the bundle holds is exactly what the evaluator reads.
struct BundleClip {
  std::string name;
  LodClip clip;
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
  std::vector<BundleClip> clips; // each of the level's joint count, all of one blend frames
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
// finite affine inverse binds, clips whose joint count is the level's and whose storage keeps
// LodClip::storageProblem()'s rules, all of one blend frames, a mesh whose indices
// and joints are in range. Empty string when fine.
std::string validateBundle(const Bundle& bundle);

// The level's LodClips (copies of its clips: play them with their blendFrames()) and
// SkinningMesh. Errors: what SkinningMesh::build() refuses.
std::optional<BundleLevelRuntime> buildBundleLevel(const BundleLevel& level, std::string* out_error = nullptr);

// The bytes `clip` takes in a bundle's level section (docs/bundle-format.md, "Clip").
std::size_t bundleClipBytes(const BundleClip& clip);

// CRC-32 (IEEE 802.3, as zlib's crc32()).
std::uint32_t crc32(std::span<const std::uint8_t> bytes);

} // namespace mlod
