#include "core/asset.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <string>

namespace mlod {

Error Asset::validate() const {
  if (!std::isfinite(unitScale) || unitScale <= 0.0)
    return Error("the unit scale must be a positive number of cm per unit");
  if (skeleton.empty() && meshes.empty())
    return Error("it holds neither a skeleton nor a mesh");
  if (Error error = skeleton.validate())
    return error;
  if (skeleton.empty() && !clips.empty())
    return Error("it has animation but no skeleton");
  for (const Clip& clip : clips)
    if (Error error = clip.validate(skeleton))
      return error;
  if (!clusters.empty() && clusters.size() != clips.size())
    return Error("it carries clusters for " + std::to_string(clusters.size()) + " clips but has " +
                 std::to_string(clips.size()));
  for (std::size_t c = 0; c < clusters.size(); ++c) {
    if (clusters[c].jointCount() != skeleton.jointCount() || clusters[c].frameCount != clips[c].frameCount)
      return Error("the clusters of clip '" + clips[c].name + "' are not of its joints and frames");
    if (Error error = clusters[c].validate())
      return Error("clip '" + clips[c].name + "': " + error.message());
  }
  for (const SkinnedMesh& mesh : meshes)
    if (Error error = mesh.validate(skeleton.jointCount()))
      return error;
  return {};
}

double standingHeightCm(const Asset& asset) {
  float low = std::numeric_limits<float>::max(), high = std::numeric_limits<float>::lowest();
  for (const SkinnedMesh& mesh : asset.meshes)
    for (const glm::vec3& position : mesh.positions) {
      low = std::min(low, position.y);
      high = std::max(high, position.y);
    }
  if (low > high) // no mesh vertex: the skeleton's rest pose
    for (const glm::mat4& model : asset.skeleton.restModelMatrices()) {
      low = std::min(low, model[3].y);
      high = std::max(high, model[3].y);
    }
  return low > high ? 0.0 : static_cast<double>(high) - static_cast<double>(low);
}

void scaleAssetLengths(Asset& asset, double factor) {
  assert(std::isfinite(factor) && factor > 0.0);
  const float f = static_cast<float>(factor);
  for (Joint& joint : asset.skeleton.joints) {
    joint.rest.translation *= f;
    if (joint.inverseBind)
      (*joint.inverseBind)[3] = glm::vec4(glm::vec3((*joint.inverseBind)[3]) * f, 1.0f);
  }
  for (Clip& clip : asset.clips)
    for (glm::vec3& translation : clip.translations)
      translation *= f;
  for (SkinnedMesh& mesh : asset.meshes)
    for (glm::vec3& position : mesh.positions)
      position *= f;
  asset.unitScale *= factor;
}

} // namespace mlod
