#include "core/mesh/skinning.h"

#include <cassert>

namespace mlod {

std::vector<glm::mat4> skinningPalette(const Skeleton& skeleton, std::span<const glm::mat4> models) {
  assert(models.size() == skeleton.joints.size());
  std::vector<glm::mat4> palette(models.size());
  std::vector<glm::mat4> rest;
  for (std::size_t j = 0; j < models.size(); ++j) {
    const Joint& joint = skeleton.joints[j];
    if (joint.inverseBind) {
      palette[j] = models[j] * *joint.inverseBind;
      continue;
    }
    if (rest.empty())
      rest = skeleton.restModelMatrices();
    palette[j] = models[j] * glm::inverse(rest[j]);
  }
  return palette;
}

void skinPositions(const SkinnedMesh& mesh, std::span<const glm::mat4> palette, std::vector<glm::vec3>& out_positions) {
  out_positions.resize(mesh.vertexCount());
  if (!mesh.skinned()) {
    out_positions.assign(mesh.positions.begin(), mesh.positions.end());
    return;
  }
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    const glm::vec4 p(mesh.positions[v], 1.0f);
    glm::vec3 sum(0.0f);
    for (int i = 0; i < kMaxInfluences; ++i) {
      const float w = mesh.weights[v][i];
      if (w == 0.0f)
        break; // sorted largest first
      assert(mesh.joints[v][i] < palette.size());
      sum += w * glm::vec3(palette[mesh.joints[v][i]] * p);
    }
    out_positions[v] = sum;
  }
}

std::vector<glm::vec3> posedPositions(const SkinnedMesh& mesh, const Skeleton& skeleton, const Clip& clip, int frame) {
  std::vector<glm::mat4> models;
  clip.modelMatrices(skeleton, frame, models);
  std::vector<glm::vec3> out;
  skinPositions(mesh, skinningPalette(skeleton, models), out);
  return out;
}

} // namespace mlod
