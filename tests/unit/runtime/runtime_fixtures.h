#pragma once
// Inputs and references for the runtime LOD tests: the real files of Debian's
// assimp-testmodels (imported once per test program), their JPC levels, and forward
// kinematics of a core Clip at any frame position written the plain way (nlerp between the
// two frames around it, then the hierarchy), against which the evaluator is checked.

#include "core/asset.h"
#include "core/clip.h"
#include "core/jpc/jpc.h"
#include "core/jpc/simplified_motion.h"
#include "core/lod_clip_builder.h"
#include "io/importer.h"
#include "runtime/local_to_model_job.h"

#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace mlod::test {

inline constexpr double kCmuUnitScale = 5.6444; // cm per BVH unit (docs/architecture.md: CMU preset)

// A real file, imported once (BVH at the CMU unit, everything else at its own).
inline const Asset& runtimeAsset(const std::string& relative) {
  static std::map<std::string, Asset> cache;
  auto found = cache.find(relative);
  if (found == cache.end()) {
    ImportOptions options;
    if (relative.find("BVH/") == 0)
      options.unitScale = kCmuUnitScale;
    Result<Asset> asset = importAsset(std::string(MLOD_ASSIMP_MODELS) + "/" + relative, options);
    if (!asset)
      throw std::runtime_error(relative + ": " + asset.message());
    found = cache.emplace(relative, std::move(asset).value()).first;
  }
  return found->second;
}

// The thresholds the runtime is checked at (cm·degrees; the paper's Table 1 and 0).
inline const std::vector<double>& testThresholds() {
  static const std::vector<double> thresholds{0.0, 5.0, 50.0, 300.0};
  return thresholds;
}

// JPC levels of the first clip of `relative` at testThresholds(), alpha 5 (computed once).
inline const std::vector<JpcLevelResult>& levelsOf(const std::string& relative) {
  static std::map<std::string, std::vector<JpcLevelResult>> cache;
  auto found = cache.find(relative);
  if (found == cache.end()) {
    const Asset& asset = runtimeAsset(relative);
    JpcSettings settings;
    settings.alpha = 5.0;
    settings.zeroLength = 1e-6 * asset.unitScale;
    Result<std::vector<JpcLevelResult>> levels =
        simplifyClip(asset.skeleton, asset.clips.front(), settings, testThresholds());
    if (!levels)
      throw std::runtime_error(relative + ": " + levels.message());
    found = cache.emplace(relative, std::move(levels).value()).first;
  }
  return found->second;
}

// Model-space matrices of `clip` at frame position f (frames), the plain way: per joint,
// nlerp (the shorter way) of the rotations of the frames around f, lerp of translations
// and scales, then LocalToModelJob.
inline void plainModels(const Skeleton& skeleton, const Clip& clip, double f, std::vector<glm::mat4>& out_models) {
  const int n = clip.frameCount;
  const int i0 = std::clamp(static_cast<int>(std::floor(f)), 0, std::max(n - 2, 0));
  const int i1 = std::min(i0 + 1, n - 1);
  const float a = static_cast<float>(std::clamp(f - i0, 0.0, 1.0));
  std::vector<glm::mat4> locals(static_cast<std::size_t>(clip.jointCount));
  for (int j = 0; j < clip.jointCount; ++j) {
    glm::quat q0 = clip.rotation(j, i0);
    glm::quat q1 = clip.rotation(j, i1);
    if (glm::dot(q0, q1) < 0.0f)
      q1 = -q1;
    const glm::quat q = glm::normalize(glm::quat(q0.w + (q1.w - q0.w) * a, q0.x + (q1.x - q0.x) * a,
                                                 q0.y + (q1.y - q0.y) * a, q0.z + (q1.z - q0.z) * a));
    Transform local;
    local.rotation = q;
    local.translation = clip.translation(j, i0) + (clip.translation(j, i1) - clip.translation(j, i0)) * a;
    local.scale = clip.scale(j, i0) + (clip.scale(j, i1) - clip.scale(j, i0)) * a;
    locals[static_cast<std::size_t>(j)] = toMatrix(local);
  }
  const std::vector<std::int16_t> parents = skeleton.parentIndices();
  out_models.resize(locals.size());
  LocalToModelJob job;
  job.parents = parents;
  job.locals = locals;
  job.out_models = out_models;
  if (!job.run())
    throw std::runtime_error("LocalToModelJob failed");
}

// |actual - expected| <= tolerance x max(1, |x|), element by element (cm), where x is the
// element itself in the rotation-scale columns, and the joint's position (the translation
// column as a vector) in the translation column. Why not the coordinate alone: a
// coordinate that cancels to ~1 cm (a toe end site's height, summed down from hips ~100 cm
// up) carries float rounding of the ~100 cm terms it was summed from; plain float FK itself
// is 1.1e-5 x max(1, |coordinate|) away from exact (double) FK there on CMU 01_01, so no
// float evaluator can be held to the coordinate alone. `out_literal` gets the worst ratio
// against the coordinate alone, for the record.
inline bool elementsNear(const glm::mat4& actual, const glm::mat4& expected, float tolerance, float* out_worst = nullptr,
                         float* out_literal = nullptr) {
  bool ok = true;
  float worst = 0.0f, literal = 0.0f;
  const float position = glm::length(glm::vec3(expected[3]));
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) {
      const float e = expected[c][r];
      const float difference = std::abs(actual[c][r] - e);
      const float ratio = difference / std::max({1.0f, std::abs(e), c == 3 ? position : 0.0f});
      worst = std::max(worst, ratio);
      literal = std::max(literal, difference / std::max(1.0f, std::abs(e)));
      ok = ok && ratio <= tolerance;
    }
  if (out_worst)
    *out_worst = worst;
  if (out_literal)
    *out_literal = literal;
  return ok;
}

} // namespace mlod::test
