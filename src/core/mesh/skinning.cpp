#include "core/mesh/skinning.h"

#include <cassert>

namespace mlod {

std::vector<glm::mat4> skinningPalette(const Skeleton& skeleton, std::span<const glm::mat4> models) {
  std::vector<glm::mat4> palette;
  skinningPalette(skeleton, models, palette);
  return palette;
}

void skinningPalette(const Skeleton& skeleton, std::span<const glm::mat4> models, std::vector<glm::mat4>& out_palette) {
  std::vector<glm::mat4>& palette = out_palette;
  assert(models.size() == skeleton.joints.size());
  palette.resize(models.size());
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
}

void skinPositions(const SkinnedMesh& mesh, std::span<const glm::mat4> palette, std::vector<glm::vec3>& out_positions) {
  out_positions.resize(mesh.vertexCount());
  if (!mesh.skinned()) {
    out_positions.assign(mesh.positions.begin(), mesh.positions.end());
    return;
  }
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v)
    out_positions[v] = skinPosition(mesh, palette, v);
}

std::vector<glm::vec3> posedPositions(const SkinnedMesh& mesh, const Skeleton& skeleton, const Clip& clip, int frame) {
  std::vector<glm::mat4> models;
  clip.modelMatrices(skeleton, frame, models);
  std::vector<glm::vec3> out;
  skinPositions(mesh, skinningPalette(skeleton, models), out);
  return out;
}

} // namespace mlod
