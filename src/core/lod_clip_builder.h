#pragma once
// From the authoring model to the runtime (docs/architecture.md section 5): a core Clip and the JPC
// ClusterSet of each LOD level become runtime LodClips; a Skeleton gives the evaluator its
// parents and inverse binds; a SkinnedMesh becomes a SkinningMesh. Core may include the
// runtime; the runtime never includes core.

#include "core/clip.h"
#include "core/error.h"
#include "core/jpc/cluster_set.h"
#include "core/skeleton.h"
#include "core/skinned_mesh.h"
#include "runtime/lod_clip.h"
#include "runtime/skinning_job.h"

#include <glm/glm.hpp>

#include <optional>
#include <span>
#include <vector>

namespace mlod {

// The runtime clip of `clip` at one level: `clusters` from JPC (null, or a set without
// joints, for full detail: the same clip without clusters). `looping` overrides the clip's
// own flag. `parents` (the skeleton's parentIndices(), or none) shares the clip's precision
// out along chains (LodClip's header); without them the bounds are coarser (more bytes).
// `blendFrames`: the unfreeze blending the clip is built for (LodClipSource::blendFrames);
// `precisionCm` the quantization's precision (LodClipSource::precisionCm).
// Errors: a clip or cluster set that does not validate, or that do not match.
Result<LodClip> buildLodClip(const Clip& clip, const ClusterSet* clusters = nullptr,
                             std::optional<bool> looping = std::nullopt, std::span<const std::int16_t> parents = {},
                             int blendFrames = 0, double precisionCm = kDefaultClipPrecisionCm);

// One LodClip per level, in order.
Result<std::vector<LodClip>> buildLodClips(const Clip& clip, std::span<const ClusterSet> levels,
                                           std::optional<bool> looping = std::nullopt,
                                           std::span<const std::int16_t> parents = {});

// The palette's inverse binds, one per joint: the joint's inverse bind matrix where a mesh
// is bound to it, else the inverse of its rest model matrix (as if a mesh were bound in the
// rest pose), so that a skeleton without a mesh still gets a meaningful palette.
std::vector<glm::mat4> paletteInverseBinds(const Skeleton& skeleton);

// The mesh's vertices grouped by influence count for SkinningJob. Errors: a mesh that is
// not skinned, or influences the runtime rejects.
Result<SkinningMesh> buildSkinningMesh(const SkinnedMesh& mesh, int jointCount);

} // namespace mlod
