#pragma once
// Linear blend skinning for authoring-time measurements (mesh errors in animated poses,
// bone reduction, the pixel-budget checks): p' = sum_i w_i (model_i x inverseBind_i) p.
// Plain and exact, not fast: the runtime's skinning is the engine's business.

#include "core/clip.h"
#include "core/skeleton.h"
#include "core/skinned_mesh.h"

#include <glm/glm.hpp>

#include <span>
#include <vector>

namespace mlod {

// Per joint: models[j] x the joint's inverse bind matrix (the inverse of its rest model
// matrix where it has none). `models` holds one matrix per joint (cm).
std::vector<glm::mat4> skinningPalette(const Skeleton& skeleton, std::span<const glm::mat4> models);

// Skinned positions (cm) of every vertex of `mesh` under `palette` (one matrix per joint the
// mesh uses); a mesh without weights keeps its positions.
void skinPositions(const SkinnedMesh& mesh, std::span<const glm::mat4> palette, std::vector<glm::vec3>& out_positions);

// The positions of `mesh` at frame `frame` of `clip` on `skeleton`.
std::vector<glm::vec3> posedPositions(const SkinnedMesh& mesh, const Skeleton& skeleton, const Clip& clip, int frame);

} // namespace mlod
