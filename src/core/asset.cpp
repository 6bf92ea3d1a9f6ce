#include "core/asset.h"

#include <cmath>

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
  for (const SkinnedMesh& mesh : meshes)
    if (Error error = mesh.validate(skeleton.jointCount()))
      return error;
  return {};
}

} // namespace mlod
