#include "core/jpc/simplified_motion.h"

#include "runtime/local_to_model_job.h"

#include <algorithm>
#include <cassert>

namespace mlod {

namespace {
// Walks the frames in order and says, per joint, which frame's rotation M' uses.
class KeyCursor {
public:
  explicit KeyCursor(const ClusterSet& clusters) : m_clusters(clusters), m_next(clusters.joints.size(), 0) {}
  // The frame whose rotation joint j holds at `frame` (frames must come in increasing order).
  int source(std::size_t joint, int frame) {
    const std::vector<Cluster>& list = m_clusters.joints[joint];
    std::size_t& i = m_next[joint];
    while (i < list.size() && list[i].last < frame)
      ++i;
    return i < list.size() && list[i].first <= frame ? list[i].key : frame;
  }

private:
  const ClusterSet& m_clusters;
  std::vector<std::size_t> m_next;
};

class Kinematics {
public:
  explicit Kinematics(const Skeleton& skeleton)
      : m_parents(skeleton.parentIndices()), m_locals(m_parents.size()), m_models(m_parents.size()) {}
  // Model-space matrices of the pose whose local transform of joint j is clip's at frame
  // sourceFrame(j).
  template <typename SourceFrame>
  const std::vector<glm::mat4>& pose(const Clip& clip, int frame, SourceFrame&& sourceFrame) {
    for (std::size_t j = 0; j < m_locals.size(); ++j) {
      const int joint = static_cast<int>(j);
      Transform local = clip.local(joint, frame);
      local.rotation = clip.rotation(joint, sourceFrame(j));
      m_locals[j] = toMatrix(local);
    }
    LocalToModelJob job;
    job.parents = m_parents;
    job.locals = m_locals;
    job.out_models = m_models;
    [[maybe_unused]] const bool ran = job.run();
    assert(ran);
    return m_models;
  }

private:
  std::vector<std::int16_t> m_parents;
  std::vector<glm::mat4> m_locals;
  std::vector<glm::mat4> m_models;
};
} // namespace

Clip simplifiedClip(const Clip& clip, const ClusterSet& clusters) {
  assert(clusters.frameCount == clip.frameCount && clusters.jointCount() == clip.jointCount);
  Clip out = clip;
  for (int j = 0; j < clusters.jointCount(); ++j)
    for (const Cluster& cluster : clusters.joints[static_cast<std::size_t>(j)])
      for (int t = cluster.first; t <= cluster.last; ++t)
        out.rotations[out.index(j, t)] = clip.rotation(j, cluster.key);
  return out;
}

std::vector<glm::vec3> jointPositions(const Skeleton& skeleton, const Clip& clip) {
  const std::size_t joints = static_cast<std::size_t>(clip.jointCount);
  std::vector<glm::vec3> out(joints * static_cast<std::size_t>(clip.frameCount));
  Kinematics kinematics(skeleton);
  for (int t = 0; t < clip.frameCount; ++t) {
    const std::vector<glm::mat4>& models = kinematics.pose(clip, t, [t](std::size_t) { return t; });
    for (std::size_t j = 0; j < joints; ++j)
      out[static_cast<std::size_t>(t) * joints + j] = glm::vec3(models[j][3]);
  }
  return out;
}

PositionError jointPositionError(const Skeleton& skeleton, const Clip& clip, const ClusterSet& clusters,
                                 std::span<const glm::vec3> originalPositions) {
  assert(clusters.frameCount == clip.frameCount && clusters.jointCount() == clip.jointCount);
  std::vector<glm::vec3> computed;
  if (originalPositions.empty()) {
    computed = jointPositions(skeleton, clip);
    originalPositions = computed;
  }
  const std::size_t joints = static_cast<std::size_t>(clip.jointCount);
  assert(originalPositions.size() == joints * static_cast<std::size_t>(clip.frameCount));
  PositionError out;
  double sum = 0.0;
  Kinematics kinematics(skeleton);
  KeyCursor cursor(clusters);
  std::vector<int> sources(joints);
  for (int t = 0; t < clip.frameCount; ++t) {
    bool anyClustered = false;
    for (std::size_t j = 0; j < joints; ++j) {
      sources[j] = cursor.source(j, t);
      anyClustered = anyClustered || sources[j] != t;
    }
    if (!anyClustered)
      continue; // M'(t) = M(t): no error
    const std::vector<glm::mat4>& models = kinematics.pose(clip, t, [&](std::size_t j) { return sources[j]; });
    for (std::size_t j = 0; j < joints; ++j) {
      const glm::vec3 original = originalPositions[static_cast<std::size_t>(t) * joints + j];
      const double distance = glm::length(glm::dvec3(glm::vec3(models[j][3])) - glm::dvec3(original));
      out.maxCm = std::max(out.maxCm, distance);
      sum += distance;
    }
  }
  const double samples = static_cast<double>(joints) * static_cast<double>(clip.frameCount);
  out.meanCm = samples > 0.0 ? sum / samples : 0.0;
  return out;
}

} // namespace mlod
