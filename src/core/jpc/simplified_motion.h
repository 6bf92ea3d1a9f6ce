#pragma once
// The simplified motion M'(t) (Ahn & Wohn, section 4: M(t) is a superset of M'(t)) and
// how far its joints move from the original's, in cm.

#include "core/clip.h"
#include "core/jpc/cluster_set.h"
#include "core/skeleton.h"

#include <glm/glm.hpp>
#include <span>
#include <vector>

namespace mlod {

// A copy of `clip` in which every clustered joint holds its key posture's rotation
// through each of its clusters. Translations (the root's above all) and scales stay as
// animated: they are never clustered. `clusters` must validate and match the clip.
Clip simplifiedClip(const Clip& clip, const ClusterSet& clusters);

// Model-space joint positions of every frame, [frame * jointCount + joint], cm, by
// forward kinematics of `clip` (the runtime's LocalToModelJob, float).
std::vector<glm::vec3> jointPositions(const Skeleton& skeleton, const Clip& clip);

// Joint-position error of M' against M over every joint (end sites included) and frame:
// the largest and the mean distance, cm.
struct PositionError {
  double maxCm = 0.0;
  double meanCm = 0.0;
};

// `originalPositions`: jointPositions(skeleton, clip) when already computed (a saving
// when several cluster sets are compared with one clip); empty = computed here.
PositionError jointPositionError(const Skeleton& skeleton, const Clip& clip, const ClusterSet& clusters,
                                 std::span<const glm::vec3> originalPositions = {});

} // namespace mlod
