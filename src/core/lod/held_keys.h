#pragma once
// A level's motion as key frames on the source's frames, the way the glTF exporter writes it
// (docs/gltf-extension.md, "Animations: clustered spans as held keys"), and what that costs:
// - a joint's rotation is keyed at every frame except inside a cluster [first, last], which
//   is held by two keys (frames first and last) with the key posture's rotation; a joint
//   removed by bone reduction holds its frozen rotation with two keys (first and last frame);
// - such a track needs key times of its own (4 bytes a key besides the 16 of a rotation),
//   where a track keyed at every frame shares one time array with every other: when the
//   held spans save less than a fifth of the frames, the track is keyed at every frame
//   instead, the held rotation repeated through each span (it plays the same, LINEAR);
// - translations and scales are keyed at every frame where the clip animates them.
// levelKeyBytes() is the figure a report states beside the exporter's: the bytes of every
// distinct time and value array the level's animations use, as 32-bit floats.

#include "core/clip.h"
#include "core/jpc/cluster_set.h"
#include "core/lod/lod_package.h"

#include <cstddef>
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

struct LevelKeyBytes {
  std::size_t rotationKeys = 0; // rotation keys of every joint and clip
  std::size_t bytes = 0;        // bytes of the distinct float arrays (key times and values) of its animations
};

// What the level's animations of every clip of `package` hold (header comment).
LevelKeyBytes levelKeyBytes(const LodPackage& package, const LodPackageLevel& level);

} // namespace mlod
