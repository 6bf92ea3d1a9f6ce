#pragma once
// A level's motion as key frames on the source's frames, the way the glTF exporter writes it
// (docs/gltf-extension.md, "Animations: clustered spans as held keys"), and what that costs:
// - a joint's rotation is keyed at every frame except inside a cluster [first, last], which
//   is held by two keys (frames first and last) with the key posture's rotation; a joint
//   removed by bone reduction holds its frozen rotation with two keys (first and last frame);
// - rotations are stored as normalized signed 16-bit integers (glTF core allows them for
//   rotation outputs; quantizeRotations()), 8 bytes a key;
// - such a track needs key times of its own (4 bytes a key besides the 8 of a rotation),
//   where a track keyed at every frame shares one time array with every other: when the
//   held spans save less than a third of the frames, the track is keyed at every frame
//   instead, the held rotation repeated through each span (it plays the same, LINEAR);
// - translations and scales are keyed at every frame where the clip animates them;
// - every clip keys every joint of the character it plays on, so that one clip played after
//   another leaves nothing of the first behind (a clip mapped onto a character drives only
//   the joints its mapping names): a joint the clip does not rotate holds its rest rotation
//   (removed by bone reduction: its frozen one) as a held track of two keys (first and last
//   frame; one for a one-frame clip), and a joint whose translation or scale another clip of
//   the package animates holds its rest value the same way.
// levelTracks() lists the tracks of one clip at one level (the glTF writer writes exactly
// those); clusterTable() is a clip's cluster table at a level as the writer stores it
// (MLOD_joint_clusters version 2, binary); levelKeyBytes() is the figure a report states
// beside the exporter's: the bytes of every distinct time and value array the level's
// animations use (times, translations and scales as 32-bit floats, rotations as 16-bit
// integers), plus the bytes of their cluster tables.

#include "core/clip.h"
#include "core/jpc/cluster_set.h"
#include "core/lod/lod_package.h"

#include <cstddef>
#include <cstdint>
#include <glm/gtc/quaternion.hpp>
#include <span>
#include <vector>

namespace mlod {

struct HeldRotationTrack {
  std::vector<int> frames;       // ascending frame indices of the keys
  std::vector<glm::quat> values; // per key: unit, sign-aligned with the key before (dot >= 0)
};

// The rotation track of `joint` of `clip` at a level whose clusters of the joint are
// `clusters` (sorted, disjoint; may be empty), or that removed the joint (`removed`: it holds
// `frozen` throughout). Keyed at every frame where that takes fewer bytes (header comment).
HeldRotationTrack heldRotationTrack(const Clip& clip, int joint, std::span<const Cluster> clusters, bool removed,
                                    const glm::quat& frozen);

// Rotation keys as the glTF writer stores them: each component c of a unit quaternion (x, y,
// z, w) as the normalized signed 16-bit integer round(c * 32767), which glTF readers decode as
// max(i / 32767, -1) (glTF 2.0, "Animations": rotation outputs may be SHORT normalized).
// note: each component moves by at most 0.5 / 32767, so the decoded 4-vector lies within
// 1 / 32767 of the key and, normalized, turns by at most 2 asin(1 / 32767) = 0.0035 degrees
// from it (kMaxRotationQuantizationDegrees); a joint's position moves by at most that angle
// (radians) times its distance from each animated ancestor (rotationQuantizationBoundCm()).
inline constexpr double kRotationQuantizationScale = 32767.0;
inline constexpr double kMaxRotationQuantizationDegrees = 0.0034970; // 2 asin(1 / 32767), rounded up
std::vector<std::int16_t> quantizeRotations(std::span<const float> xyzw);
glm::quat dequantizeRotation(const std::int16_t* xyzw); // normalized, as a reader plays it
// The rotation angle (degrees, the shorter way) between `a` and `b`, unit or not.
double rotationAngleDegrees(const glm::quat& a, const glm::quat& b);

enum class TrackPath { Rotation, Translation, Scale };

// One animated property of one joint, in glTF's units and layout.
struct LevelTrack {
  int joint = 0;
  TrackPath path = TrackPath::Rotation;
  std::vector<int> frames;   // ascending frame indices of the keys
  std::vector<float> values; // per key: x, y, z, w (rotation: unit, sign-aligned with the key
                             // before), or x, y, z (translation in metres, scale)
  int components() const { return path == TrackPath::Rotation ? 4 : 3; }
};

// The tracks of `package.clips[clip]` at `level` (header comment), joint by joint, rotation
// before translation before scale. Every joint has a rotation track. The clip must animate
// the package's skeleton; cluster sets of another skeleton are ignored (the writer refuses
// them first).
std::vector<LevelTrack> levelTracks(const LodPackage& package, const LodPackageLevel& level, std::size_t clip);

// A clip's clusters at a level as one table (docs/gltf-extension.md, MLOD_joint_clusters
// version 2): a row (joint, first, last, key) per cluster, joints ascending, each joint's
// clusters in their order, stored as unsigned 16-bit integers where every value fits (joint
// and frame indices below 65,536), else 32-bit. Empty when the clip has no cluster.
struct ClusterTable {
  std::vector<std::uint32_t> rows; // 4 values per cluster
  bool wide = false;               // 32-bit integers rather than 16-bit
  std::size_t clusters() const { return rows.size() / 4; }
  std::size_t bytes() const { return rows.size() * (wide ? 4 : 2); }
};
ClusterTable clusterTable(const ClusterSet& clusters);

struct LevelKeyBytes {
  std::size_t rotationKeys = 0; // rotation keys of every joint and clip
  std::size_t clusterBytes = 0; // bytes of its clips' cluster tables (clusterTable())
  std::size_t bytes = 0;        // bytes of the distinct float arrays (key times and values) of its
                                // animations, plus clusterBytes
};

// What the level's animations of every clip of `package` hold (header comment).
LevelKeyBytes levelKeyBytes(const LodPackage& package, const LodPackageLevel& level);

// A bound (cm) of how far any joint of `skeleton` moves when every joint's rotation turns by
// up to `degrees` (radians inside): the largest, over the joints, of the angle times the sum
// of the path lengths (bone lengths, in rest pose; the same in every pose) to each strict
// ancestor. First order in the angle, which at 0.0035 degrees is exact to 1e-9.
double rotationQuantizationBoundCm(const Skeleton& skeleton, double degrees = kMaxRotationQuantizationDegrees);

} // namespace mlod
