#pragma once
// Inputs for the JPC tests: a synthetic 3-joint chain with hand-computable errors, and
// the real clips of Debian's assimp-testmodels (imported once per test program).

#include "core/asset.h"
#include "core/clip.h"
#include "core/jpc/posture_error.h"
#include "io/importer.h"
#include "unit/core/fixtures.h"

#include <functional>
#include <glm/gtc/quaternion.hpp>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace mlod::test {

inline glm::quat axisAngle(float degrees, const glm::vec3& axis) {
  return glm::angleAxis(glm::radians(degrees), glm::normalize(axis));
}

// The chain j0 -> j1 -> j2 of makeChain(3, 10 cm): j0 and j1 carry rotation channels, j2
// is a leaf without one (an End Site). j0 holds still; j1 takes rotation(frame). For j1,
// r = 10 cm and the child direction is +y, so a rotation by d degrees about z from one
// frame to another gives E = 10 d + alpha d.
inline Clip chainClip(const Skeleton& chain, int frames, const std::function<glm::quat(int)>& rotation) {
  Clip clip = Clip::restPose(chain, frames, 30.0);
  clip.name = "chain";
  clip.hasRotation = {1, 1, 0};
  for (int t = 0; t < frames; ++t)
    clip.rotations[clip.index(1, t)] = rotation(t);
  return clip;
}

// j1's error track in chainClip().
inline JointTrack chainTrack(const Clip& clip, double alpha) {
  const std::vector<JointGeometry> geometry = jointGeometry(makeChain(3, 10.0f));
  return JointTrack(
      geometry[1], alpha,
      std::span<const glm::quat>(&clip.rotations[clip.index(1, 0)], static_cast<std::size_t>(clip.frameCount)));
}

// A real file, imported once (CMU clips at 5.6444 cm per unit, as the paper's Table 1
// needs; everything else at its own unit).
inline const Asset& realAsset(const std::string& relative) {
  static std::map<std::string, Asset> cache;
  auto found = cache.find(relative);
  if (found == cache.end()) {
    ImportOptions options;
    if (relative.find("BVH/") == 0)
      options.unitScale = 5.6444;
    Result<Asset> asset = importAsset(std::string(MLOD_ASSIMP_MODELS) + "/" + relative, options);
    if (!asset)
      throw std::runtime_error(relative + ": " + asset.message());
    found = cache.emplace(relative, std::move(asset).value()).first;
  }
  return found->second;
}

// `source` looped or cut to `frames` frames (scripts/check-docs-figures.sh makes the long
// BVHs of the memory table so; a cut one is a frame range of a long clip).
inline Clip repeated(const Clip& source, int frames) {
  Clip out = source;
  out.frameCount = frames;
  const std::size_t total = static_cast<std::size_t>(frames) * static_cast<std::size_t>(source.jointCount);
  out.rotations.resize(total);
  out.translations.resize(total);
  out.scales.resize(total);
  for (int j = 0; j < source.jointCount; ++j)
    for (int t = 0; t < frames; ++t) {
      const std::size_t from = source.index(j, t % source.frameCount);
      out.rotations[out.index(j, t)] = source.rotations[from];
      out.translations[out.index(j, t)] = source.translations[from];
      out.scales[out.index(j, t)] = source.scales[from];
    }
  return out;
}

// Joint j's rotations in `clip`, frames [first, first + count).
inline std::span<const glm::quat> rotationsOf(const Clip& clip, int joint, int first = 0, int count = -1) {
  if (count < 0)
    count = clip.frameCount - first;
  return {&clip.rotations[clip.index(joint, first)], static_cast<std::size_t>(count)};
}

} // namespace mlod::test
