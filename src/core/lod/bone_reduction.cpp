#include "core/lod/bone_reduction.h"

#include "core/cancel.h"
#include "core/jpc/parallel_for.h"
#include "core/jpc/posture_error.h"
#include "runtime/transform.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>

namespace mlod {

namespace {

struct FrozenPose {
  int key = 0;
  double maxError = 0.0; // cm·degrees
};

bool near(const glm::vec3& a, const glm::vec3& b, float tolerance) {
  return glm::length(a - b) <= tolerance * std::max(1.0f, glm::length(b));
}

// What a joint's frozen pose depends on whatever the threshold (BoneReductionCache), and what
// the searches so far found.
struct JointFacts {
  double alpha = 0.0, zeroLength = 0.0; // made with
  bool restTranslation = true;          // translation and scale at rest in every frame
  std::vector<glm::quat> rotations;     // every frame of every clip, one after another
  JointTrack track;
  std::vector<int> frames;     // one frame per run of identical frames: the others give the same errors
  std::vector<double> row0;    // E(t, 0) per frame
  std::vector<double> rowFar;  // E(t, far) per frame; empty until a search needs it
  double farthest = 0.0;       // max_t E(t, 0)
  int far = 0;                 // the frame of it
  std::optional<FrozenPose> found;
  double notWithin = -1.0; // the largest threshold searched in vain (-1: none)
};

JointFacts jointFacts(const Skeleton& skeleton, std::span<const Clip> clips, const JointGeometry& geometry, int j,
                      double alpha, double zeroLength) {
  const Joint& joint = skeleton.joints[static_cast<std::size_t>(j)];
  JointFacts out;
  out.alpha = alpha;
  out.zeroLength = zeroLength;
  for (const Clip& clip : clips)
    for (int t = 0; t < clip.frameCount && out.restTranslation; ++t) {
      out.restTranslation = near(clip.translation(j, t), joint.rest.translation, 1e-5f) &&
                            near(clip.scale(j, t), joint.rest.scale, 1e-5f);
      out.rotations.push_back(clip.rotation(j, t));
    }
  if (!out.restTranslation)
    return out;
  out.track = JointTrack(geometry, alpha, out.rotations);
  const int n = out.track.frameCount();
  for (int t = 0; t < n; ++t)
    if (!out.track.sameAsPrevious(t))
      out.frames.push_back(t);
  out.row0.assign(static_cast<std::size_t>(n), 0.0);
  for (int t : out.frames) {
    out.row0[static_cast<std::size_t>(t)] = out.track.error(t, 0);
    if (out.row0[static_cast<std::size_t>(t)] > out.farthest) {
      out.farthest = out.row0[static_cast<std::size_t>(t)];
      out.far = t;
    }
  }
  return out;
}

// The frame k with the smallest max_t E(t, k), if that is within `threshold`; none once
// `cancel` is set (the caller tells the two apart). Each candidate k can be O(n).
// note: the answer is the first k (in frame order) of the smallest max_t E(t, k), m*, when
// m* <= threshold, whatever the threshold: once found it answers every threshold, and a
// search in vain at T answers every threshold up to T (m* > T)
std::optional<FrozenPose> frozenPose(JointFacts& joint, double threshold, const std::atomic<bool>* cancel) {
  const JointTrack& track = joint.track;
  if (joint.farthest == 0.0)
    return FrozenPose{0, 0.0};
  // note: E is a pseudometric (posture_error.h), so for any k, max(E(0, k), E(far, k)) >=
  // E(0, far) / 2: a joint whose frames span more than twice the bound cannot be frozen
  if (joint.farthest > 2.0 * threshold * (1.0 + 1e-9) + 1e-12)
    return std::nullopt;
  if (joint.found)
    return joint.found->maxError <= threshold ? joint.found : std::nullopt;
  if (threshold <= joint.notWithin)
    return std::nullopt;
  const int n = track.frameCount();
  if (joint.rowFar.empty()) {
    joint.rowFar.assign(static_cast<std::size_t>(n), 0.0);
    for (int t : joint.frames)
      joint.rowFar[static_cast<std::size_t>(t)] = track.error(t, joint.far);
  }
  const std::vector<double>& row0 = joint.row0;
  const std::vector<double>& rowFar = joint.rowFar;
  double best = std::numeric_limits<double>::infinity();
  int key = -1;
  for (int k : joint.frames) {
    if (cancelled(cancel))
      return std::nullopt; // (nothing learnt)
    const double bound = std::min(threshold, best);
    double worst = std::max(row0[static_cast<std::size_t>(k)], rowFar[static_cast<std::size_t>(k)]);
    if (worst > bound || (worst == best && key >= 0))
      continue;
    bool within = true;
    for (int t : joint.frames) {
      worst = std::max(worst, track.error(t, k));
      if (worst > bound || worst >= best) {
        within = false;
        break;
      }
    }
    if (within) {
      best = worst;
      key = k;
    }
  }
  if (key < 0) {
    joint.notWithin = std::max(joint.notWithin, threshold);
    return std::nullopt;
  }
  joint.found = FrozenPose{key, best};
  return joint.found;
}

// The local matrix of a removed joint: rest translation and scale, frozen rotation.
glm::mat4 frozenLocal(const Skeleton& skeleton, const BoneReduction& reduction, int joint) {
  Transform t = skeleton.joints[static_cast<std::size_t>(joint)].rest;
  t.rotation = reduction.frozenRotation[static_cast<std::size_t>(joint)];
  return toMatrix(t);
}

// The frozen transforms of the removed joints from just below `active` down to `joint`'s
// parent (identity when the parent is active): what hangs `joint` from its active ancestor.
glm::mat4 foldAbove(const Skeleton& skeleton, const BoneReduction& reduction, int joint) {
  glm::mat4 fold(1.0f);
  for (int r = skeleton.joints[static_cast<std::size_t>(joint)].parent; r >= 0 && reduction.removed[std::size_t(r)];
       r = skeleton.joints[static_cast<std::size_t>(r)].parent)
    fold = frozenLocal(skeleton, reduction, r) * fold;
  return fold;
}

glm::quat sameHemisphere(glm::quat q, const glm::quat& previous) { return glm::dot(q, previous) < 0.0f ? -q : q; }

} // namespace

int BoneReduction::removedCount() const {
  return static_cast<int>(std::count(removed.begin(), removed.end(), std::uint8_t(1)));
}

struct BoneReductionCache::State {
  std::mutex mutex;
  std::vector<std::unique_ptr<JointFacts>> joints; // per joint of the skeleton
};

BoneReductionCache::BoneReductionCache() : m_state(std::make_unique<State>()) {}
BoneReductionCache::~BoneReductionCache() = default;

Result<BoneReduction> reduceBones(const Skeleton& skeleton, std::span<const Clip> clips, double threshold,
                                  const JpcSettings& settings, int level, const std::atomic<bool>* cancel) {
  return reduceBones(skeleton, clips, threshold, settings, level, cancel, nullptr);
}

Result<BoneReduction> reduceBones(const Skeleton& skeleton, std::span<const Clip> clips, double threshold,
                                  const JpcSettings& settings, int level, const std::atomic<bool>* cancel,
                                  BoneReductionCache* cache) {
  if (Error error = skeleton.validate())
    return Error("skeleton: " + error.message());
  if (clips.empty())
    return Error("bone reduction: no clip to judge the joints by");
  for (const Clip& clip : clips)
    if (Error error = clip.validate(skeleton))
      return Error("clip '" + clip.name + "': " + error.message());
  if (Error error = settings.validate(skeleton))
    return error;
  if (Error error = validateThreshold(threshold))
    return error;

  const std::size_t n = skeleton.joints.size();
  BoneReduction out;
  out.removed.assign(n, 0);
  out.frozenError.assign(n, 0.0);
  for (const Joint& joint : skeleton.joints)
    out.frozenRotation.push_back(joint.rest.rotation);
  const std::vector<JointGeometry> geometry = jointGeometry(skeleton, settings.zeroLength);
  std::unique_lock<std::mutex> lock;
  std::vector<std::unique_ptr<JointFacts>> made;
  std::vector<std::unique_ptr<JointFacts>>& facts = cache ? cache->state().joints : made;
  if (cache)
    lock = std::unique_lock<std::mutex>(cache->state().mutex);
  facts.resize(n);
  // note: joints are independent (each writes its own slots), so they are judged on every
  // core; the result does not depend on the order
  std::vector<std::optional<FrozenPose>> frozen(n);
  parallelFor(static_cast<int>(n) - 1, 0, [&](int i) {
    const std::size_t j = std::size_t(i) + 1;
    const Joint& joint = skeleton.joints[j];
    if (cancelled(cancel) || settings.lockedFor(joint.name))
      return;
    const double alpha = settings.alphaFor(joint.name);
    std::unique_ptr<JointFacts>& known = facts[j];
    if (!known || known->alpha != alpha || known->zeroLength != settings.zeroLength)
      known = std::make_unique<JointFacts>(jointFacts(skeleton, clips, geometry[j], int(j), alpha, settings.zeroLength));
    if (known->restTranslation) // an animated translation or scale is never frozen (docs/architecture.md section 4)
      frozen[j] = frozenPose(*known, settings.thresholdFor(joint.name, level, threshold), cancel);
  });
  if (cancelled(cancel))
    return Error(kCancelled);
  for (std::size_t j = 1; j < n; ++j) {
    if (!frozen[j])
      continue;
    out.removed[j] = 1;
    out.frozenRotation[j] = glm::normalize(facts[j]->rotations[static_cast<std::size_t>(frozen[j]->key)]);
    out.frozenError[j] = frozen[j]->maxError;
  }

  out.activeAncestor.assign(n, 0);
  out.reducedIndex.assign(n, -1);
  for (std::size_t j = 0; j < n; ++j) {
    const int parent = skeleton.joints[j].parent;
    out.activeAncestor[j] = out.removed[j] ? out.activeAncestor[static_cast<std::size_t>(parent)] : int(j);
    if (out.removed[j])
      continue;
    out.reducedIndex[j] = static_cast<int>(out.fullIndex.size());
    out.fullIndex.push_back(int(j));
    Joint reduced = skeleton.joints[j];
    if (parent >= 0) {
      reduced.parent = out.reducedIndex[static_cast<std::size_t>(out.activeAncestor[static_cast<std::size_t>(parent)])];
      reduced.rest = decompose(foldAbove(skeleton, out, int(j)) * toMatrix(skeleton.joints[j].rest));
    }
    out.skeleton.joints.push_back(reduced);
  }
  return out;
}

Clip frozenClip(const BoneReduction& reduction, Clip clip) {
  for (int j = 0; j < clip.jointCount; ++j)
    if (reduction.removed[static_cast<std::size_t>(j)])
      for (int t = 0; t < clip.frameCount; ++t)
        clip.rotations[clip.index(j, t)] = reduction.frozenRotation[static_cast<std::size_t>(j)];
  return clip;
}

Clip reduceClip(const BoneReduction& reduction, const Skeleton& full, const Clip& clip) {
  assert(clip.jointCount == full.jointCount());
  Clip out;
  out.name = clip.name;
  out.fps = clip.fps;
  out.frameCount = clip.frameCount;
  out.looping = clip.looping;
  out.jointCount = static_cast<int>(reduction.fullIndex.size());
  const std::size_t size = static_cast<std::size_t>(out.jointCount) * static_cast<std::size_t>(clip.frameCount);
  out.rotations.resize(size);
  out.translations.resize(size);
  out.scales.resize(size);
  for (int r = 0; r < out.jointCount; ++r) {
    const int j = reduction.fullIndex[static_cast<std::size_t>(r)];
    out.hasRotation.push_back(clip.hasRotation[static_cast<std::size_t>(j)]);
    out.hasTranslation.push_back(clip.hasTranslation[static_cast<std::size_t>(j)]);
    out.hasScale.push_back(clip.hasScale[static_cast<std::size_t>(j)]);
  }
  // note: each joint's keys are its own, so joints are folded on every core
  parallelFor(out.jointCount, 0, [&](int r) {
    const int j = reduction.fullIndex[static_cast<std::size_t>(r)];
    const glm::mat4 fold = foldAbove(full, reduction, j);
    const bool folded = fold != glm::mat4(1.0f);
    for (int t = 0; t < clip.frameCount; ++t) {
      const std::size_t i = out.index(r, t);
      if (!folded) {
        out.rotations[i] = clip.rotation(j, t);
        out.translations[i] = clip.translation(j, t);
        out.scales[i] = clip.scale(j, t);
        continue;
      }
      const Transform local = decompose(fold * toMatrix(clip.local(j, t)));
      out.rotations[i] = t > 0 ? sameHemisphere(local.rotation, out.rotations[out.index(r, t - 1)]) : local.rotation;
      out.translations[i] = local.translation;
      out.scales[i] = local.scale;
    }
  });
  return out;
}

std::vector<glm::mat4> bakeMatrices(const BoneReduction& reduction, const Skeleton& full) {
  const std::size_t n = full.joints.size();
  const std::vector<glm::mat4> rest = full.restModelMatrices();
  const auto inverseBind = [&](std::size_t j) {
    return full.joints[j].inverseBind ? *full.joints[j].inverseBind : glm::inverse(rest[j]);
  };
  // B_r = bind(a) * F_r * inverseBind(r): the removed joint's skin as its active ancestor sees it
  std::vector<glm::mat4> bake(n, glm::mat4(1.0f));
  for (std::size_t j = 0; j < n; ++j) {
    if (!reduction.removed[j])
      continue;
    const auto a = static_cast<std::size_t>(reduction.activeAncestor[j]);
    const glm::mat4 chain = foldAbove(full, reduction, int(j)) * frozenLocal(full, reduction, int(j));
    bake[j] = glm::inverse(inverseBind(a)) * chain * inverseBind(j);
  }
  return bake;
}

SkinnedMesh rebindMesh(const BoneReduction& reduction, const Skeleton& full, const SkinnedMesh& mesh) {
  SkinnedMesh out = mesh;
  if (!mesh.skinned())
    return out;
  const std::vector<glm::mat4> bake = bakeMatrices(reduction, full);
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    const glm::vec4& w = mesh.weights[v];
    const glm::u16vec4& joints = mesh.joints[v];
    glm::vec3 position(0.0f), normal(0.0f);
    int targets[kMaxInfluences];
    float weights[kMaxInfluences];
    int count = 0;
    bool baked = false;
    for (int i = 0; i < kMaxInfluences; ++i) {
      if (w[i] == 0.0f)
        break;
      const std::size_t j = joints[i];
      baked |= reduction.removed[j] != 0;
      position += w[i] * glm::vec3(bake[j] * glm::vec4(mesh.positions[v], 1.0f));
      if (!mesh.normals.empty())
        normal += w[i] * glm::vec3(bake[j] * glm::vec4(mesh.normals[v], 0.0f));
      const int target = reduction.reducedIndex[static_cast<std::size_t>(reduction.activeAncestor[j])];
      int k = 0;
      while (k < count && targets[k] != target)
        ++k;
      if (k == count) {
        targets[count] = target;
        weights[count] = 0.0f;
        ++count;
      }
      weights[k] += w[i];
    }
    if (baked) {
      out.positions[v] = position;
      if (!mesh.normals.empty() && glm::length(normal) > 0.0f)
        out.normals[v] = glm::normalize(normal);
    }
    normalizeInfluences(targets, weights, count, out.joints[v], out.weights[v]);
  }
  return out;
}

} // namespace mlod
