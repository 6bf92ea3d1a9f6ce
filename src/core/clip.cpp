#include "core/clip.h"

#include "runtime/local_to_model_job.h"

#include <cmath>

namespace mlod {

namespace {
bool isFinite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
bool isFinite(const glm::quat& q) {
  return std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z) && std::isfinite(q.w);
}
} // namespace

Clip Clip::restPose(const Skeleton& skeleton, int frames, double framesPerSecond) {
  assert(frames >= 1);
  Clip clip;
  clip.name = "rest";
  clip.fps = framesPerSecond;
  clip.frameCount = frames;
  clip.jointCount = skeleton.jointCount();
  const std::size_t n = static_cast<std::size_t>(clip.jointCount) * static_cast<std::size_t>(frames);
  clip.rotations.resize(n);
  clip.translations.resize(n);
  clip.scales.resize(n);
  for (int j = 0; j < clip.jointCount; ++j) {
    const Transform& rest = skeleton.joints[static_cast<std::size_t>(j)].rest;
    for (int f = 0; f < frames; ++f) {
      clip.rotations[clip.index(j, f)] = rest.rotation;
      clip.translations[clip.index(j, f)] = rest.translation;
      clip.scales[clip.index(j, f)] = rest.scale;
    }
  }
  clip.hasRotation.assign(static_cast<std::size_t>(clip.jointCount), 0);
  clip.hasTranslation.assign(static_cast<std::size_t>(clip.jointCount), 0);
  clip.hasScale.assign(static_cast<std::size_t>(clip.jointCount), 0);
  return clip;
}

Transform Clip::local(int joint, int frame) const {
  return Transform{translation(joint, frame), rotation(joint, frame), scale(joint, frame)};
}

void Clip::modelMatrices(const Skeleton& skeleton, int frame, std::vector<glm::mat4>& out_models) const {
  std::vector<glm::mat4> locals(static_cast<std::size_t>(jointCount));
  for (int j = 0; j < jointCount; ++j)
    locals[static_cast<std::size_t>(j)] = toMatrix(local(j, frame));
  const std::vector<std::int16_t> parents = skeleton.parentIndices();
  out_models.resize(locals.size());
  LocalToModelJob job;
  job.parents = parents;
  job.locals = locals;
  job.out_models = out_models;
  [[maybe_unused]] const bool ran = job.run();
  assert(ran);
}

int Clip::rotationChannelCount() const {
  int count = 0;
  for (std::uint8_t flag : hasRotation)
    count += flag ? 1 : 0;
  return count;
}

Error Clip::validate(const Skeleton& skeleton) const {
  const std::string where = "clip '" + name + "'";
  if (name.empty())
    return Error("a clip has no name");
  if (!std::isfinite(fps) || fps <= 0.0 || fps > 10000.0)
    return Error(where + " has frame rate " + std::to_string(fps) + "; it must be in (0, 10000] fps");
  if (frameCount < 1)
    return Error(where + " has no frames");
  if (jointCount != skeleton.jointCount())
    return Error(where + " animates " + std::to_string(jointCount) + " joints but the skeleton has " +
                 std::to_string(skeleton.jointCount()));
  const std::size_t n = static_cast<std::size_t>(jointCount) * static_cast<std::size_t>(frameCount);
  if (rotations.size() != n || translations.size() != n || scales.size() != n)
    return Error(where + " has tracks of the wrong length");
  const std::size_t joints = static_cast<std::size_t>(jointCount);
  if (hasRotation.size() != joints || hasTranslation.size() != joints || hasScale.size() != joints)
    return Error(where + " has channel flags of the wrong length");
  for (int j = 0; j < jointCount; ++j) {
    for (int f = 0; f < frameCount; ++f) {
      const std::size_t i = index(j, f);
      const char* bad = nullptr;
      if (!isFinite(rotations[i]))
        bad = "a non-finite rotation";
      else if (std::abs(glm::length(rotations[i]) - 1.0f) > 1e-3f)
        bad = "a rotation that is not a unit quaternion";
      else if (!isFinite(translations[i]))
        bad = "a non-finite translation";
      else if (!isFinite(scales[i]))
        bad = "a non-finite scale";
      if (bad)
        return Error(where + " has " + bad + " at joint '" + skeleton.joints[static_cast<std::size_t>(j)].name +
                     "', frame " + std::to_string(f));
    }
  }
  return {};
}

} // namespace mlod
