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
// The same into `out_palette` (resized; no allocation once it has the size).
void skinningPalette(const Skeleton& skeleton, std::span<const glm::mat4> models, std::vector<glm::mat4>& out_palette);

// The skinned position (cm) of vertex v of a skinned `mesh` under `palette`: what
// skinPositions() gives it, to the bit (it calls this).
inline glm::vec3 skinPosition(const SkinnedMesh& mesh, std::span<const glm::mat4> palette, std::size_t v) {
  const glm::vec4 p(mesh.positions[v], 1.0f);
  glm::vec3 sum(0.0f);
  for (int i = 0; i < kMaxInfluences; ++i) {
    const float w = mesh.weights[v][i];
    if (w == 0.0f)
      break; // sorted largest first
    sum += w * glm::vec3(palette[mesh.joints[v][i]] * p);
  }
  return sum;
}

// Skinned positions (cm) of every vertex of `mesh` under `palette` (one matrix per joint the
// mesh uses); a mesh without weights keeps its positions.
void skinPositions(const SkinnedMesh& mesh, std::span<const glm::mat4> palette, std::vector<glm::vec3>& out_positions);

// The positions of `mesh` at frame `frame` of `clip` on `skeleton`.
std::vector<glm::vec3> posedPositions(const SkinnedMesh& mesh, const Skeleton& skeleton, const Clip& clip, int frame);

} // namespace mlod
