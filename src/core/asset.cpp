#include "core/asset.h"

#include <cmath>
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

} // namespace mlod
