#include "core/lod/lod_character.h"

#include "core/jpc/parallel_for.h"
#include "core/jpc/simplified_motion.h"
#include "core/mesh/skinning.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace mlod {

namespace {

// Positions of what the error is measured on at one frame: skin vertices, or joints.
void render(const Skeleton& skeleton, const Clip& clip, int frame, const SkinnedMesh* mesh,
            std::vector<glm::mat4>& models, std::vector<glm::vec3>& out_points) {
  clip.modelMatrices(skeleton, frame, models);
  if (mesh) {
    skinPositions(*mesh, skinningPalette(skeleton, models), out_points);
    return;
  }
  out_points.resize(models.size());
  for (std::size_t j = 0; j < models.size(); ++j)
    out_points[j] = glm::vec3(models[j][3]);
}

} // namespace

Result<LodCharacter> LodCharacter::prepare(const Skeleton& skeleton, const SkinnedMesh* mesh, std::span<const Clip> clips,
                                           const JpcSettings& jpc, const MeshLodSettings& meshSettings,
                                           const std::atomic<bool>* cancel) {
  if (Error error = skeleton.validate())
    return Error("skeleton: " + error.message());
  if (clips.empty())
    return Error("LOD: the character plays no clip");
  if (mesh)
    if (Error error = mesh->validate(skeleton.jointCount()))
      return Error("mesh '" + mesh->name + "': " + error.message());
  if (Error error = meshSettings.validate())
    return error;
  LodCharacter out;
  out.m_skeleton = skeleton;
  if (mesh) {
    out.m_mesh = *mesh;
    out.m_deviation = SkinDeviation(*mesh);
  }
  out.m_clips.assign(clips.begin(), clips.end());
  out.m_jpc = jpc;
  out.m_meshSettings = meshSettings;
  if (cancel)
    out.m_meshSettings.cancel = cancel;
  cancel = out.m_meshSettings.cancel;
  for (const Clip& clip : clips) {
    if (cancelled(cancel))
      return Error(kCancelled);
    Result<JpcClip> prepared = JpcClip::prepare(skeleton, clip, jpc);
    if (!prepared)
      return Error("clip '" + clip.name + "': " + prepared.message());
    out.m_prepared.push_back(std::move(prepared).value());
  }
  // note: the radius is a maximum, so stretches of frames are rendered on every core, each
  // into its own slot; the largest of them is the same whatever the split
  constexpr int kStretch = 256; // frames per task
  std::vector<std::pair<std::size_t, int>> tasks; // (clip, first frame)
  for (std::size_t c = 0; c < clips.size(); ++c)
    for (int t = 0; t < clips[c].frameCount; t += kStretch)
      tasks.emplace_back(c, t);
  std::vector<double> radii(tasks.size(), 0.0);
  parallelFor(static_cast<int>(tasks.size()), 0, [&](int task) {
    const auto [c, first] = tasks[std::size_t(task)];
    const Clip& clip = clips[c];
    std::vector<glm::mat4> models;
    std::vector<glm::vec3> points;
    double& radius = radii[std::size_t(task)];
    for (int t = first; t < std::min(clip.frameCount, first + kStretch) && !cancelled(cancel); ++t) {
      render(skeleton, clip, t, mesh, models, points);
      const glm::vec3 root(models[0][3]);
      for (const glm::vec3& p : points)
        radius = std::max(radius, double(glm::length(p - root)));
    }
  });
  if (cancelled(cancel))
    return Error(kCancelled);
  for (double radius : radii)
    out.m_radius = std::max(out.m_radius, radius);
  return out;
}

Result<LevelMotion> LodCharacter::motionAt(double threshold, int level) const {
  return motionAt(threshold, level, MotionError::Exact);
}

Result<LevelMotion> LodCharacter::motionAt(double threshold, int level, MotionError measure) const {
  if (Error error = validateThreshold(threshold))
    return error;
  const std::atomic<bool>* cancel = m_meshSettings.cancel;
  if (cancelled(cancel))
    return Error(kCancelled);
  LevelMotion out;
  out.threshold = threshold;
  Result<BoneReduction> bones = reduceBones(m_skeleton, m_clips, threshold, m_jpc, level, cancel, m_boneFacts.get());
  if (!bones)
    return bones.error();
  out.bones = std::move(bones).value();
  if (m_mesh)
    out.mesh = rebindMesh(out.bones, m_skeleton, *m_mesh);

  std::vector<glm::mat4> models;
  std::vector<glm::vec3> original, simplified;
  const SkinnedMesh* originalMesh = m_mesh ? &*m_mesh : nullptr;
  const SkinnedMesh* levelMesh = out.mesh ? &*out.mesh : nullptr;
  double clusteredJointFrames = 0.0, jointFrames = 0.0;
  for (std::size_t c = 0; c < m_clips.size(); ++c) {
    const Clip& clip = m_clips[c];
    ClusterSet clusters;
    clusters.frameCount = clip.frameCount;
    std::vector<JointClustering> joints = clusterClip(c, level, threshold);
    if (cancelled(cancel))
      return Error(kCancelled);
    if (m_work->exhausted())
      return Error(workLimitMessage(clip.name, *m_work, "the LOD set's motion search",
                                    "for every threshold it tries, every joint together",
                                    "trim the clip, lock joints or give the levels' thresholds in a project"));
    for (JointClustering& joint : joints) {
      clusteredJointFrames += joint.clusteredFrames;
      clusters.joints.push_back(std::move(joint.clusters));
    }
    jointFrames += double(m_prepared[c].clusterableCount()) * clip.frameCount;
    const Clip full = frozenClip(out.bones, simplifiedClip(clip, clusters));
    out.clips.push_back(reduceClip(out.bones, m_skeleton, full));
    out.clusters.push_back(std::move(clusters));
    const Clip& reduced = out.clips.back();
    if (levelMesh && originalMesh->skinned()) { // the same maximum as the loop below, far fewer frames skinned
      const bool bound = measure == MotionError::Bound;
      Result<double> largest = bound ? m_deviation.bound(m_skeleton, *originalMesh, clip, out.bones, *levelMesh,
                                                         reduced, out.motionErrorCm, cancel)
                                     : m_deviation.measure(m_skeleton, *originalMesh, clip, out.bones, *levelMesh,
                                                           reduced, out.motionErrorCm, cancel);
      if (!largest)
        return largest.error();
      out.motionErrorCm = *largest;
      out.motionErrorExact = !bound;
      continue;
    }
    for (int t = 0; t < clip.frameCount; ++t) {
      if (cancelled(cancel))
        return Error(kCancelled);
      render(m_skeleton, clip, t, originalMesh, models, original);
      render(out.bones.skeleton, reduced, t, levelMesh, models, simplified);
      if (!levelMesh) { // joints: compare the active ones with their own originals
        for (std::size_t r = 0; r < simplified.size(); ++r)
          out.motionErrorCm = std::max(
              out.motionErrorCm,
              double(glm::length(simplified[r] - original[std::size_t(out.bones.fullIndex[r])])));
        continue;
      }
      for (std::size_t v = 0; v < original.size(); ++v)
        out.motionErrorCm = std::max(out.motionErrorCm, double(glm::length(simplified[v] - original[v])));
    }
  }
  out.simplifiedPercent = jointFrames > 0.0 ? 100.0 * clusteredJointFrames / jointFrames : 0.0;
  return out;
}

std::vector<JointClustering> LodCharacter::clusterClip(std::size_t c, int level, double threshold) const {
  const JpcClip& prepared = m_prepared[c];
  const std::atomic<bool>* cancel = m_meshSettings.cancel;
  const int joints = prepared.jointCount();
  std::vector<JointClustering> out(static_cast<std::size_t>(joints));
  std::vector<ClusteringKey> keys(static_cast<std::size_t>(joints));
  std::vector<int> missing;
  {
    const std::lock_guard<std::mutex> lock(m_clusterings->mutex);
    for (int j = 0; j < joints; ++j) {
      if (!prepared.clusterable(j) || prepared.locked(j))
        continue; // no clusters
      ClusteringKey& key = keys[std::size_t(j)];
      key = {
          int(c),           j,         prepared.threshold(j, level, threshold), m_jpc.alphaFor(prepared.jointName(j)),
          m_jpc.zeroLength, m_jpc.mode};
      const auto found = m_clusterings->kept.find(key);
      if (found != m_clusterings->kept.end())
        out[std::size_t(j)] = found->second;
      else
        missing.push_back(j);
    }
  }
  parallelFor(static_cast<int>(missing.size()), 0, [&](int i) {
    const int j = missing[std::size_t(i)];
    if (!cancelled(cancel) && !exhausted(m_work.get())) // looked at per joint
      out[std::size_t(j)] = prepared.clusterJoint(j, level, threshold, m_work.get());
  });
  if (cancelled(cancel) || m_work->exhausted())
    return out; // some joints unclustered or cut short: the caller drops the result, nothing is kept
  const std::lock_guard<std::mutex> lock(m_clusterings->mutex);
  for (int j : missing)
    m_clusterings->kept.emplace(keys[std::size_t(j)], out[std::size_t(j)]);
  m_clusterings->made += static_cast<std::int64_t>(missing.size());
  return out;
}

std::int64_t LodCharacter::jointsClustered() const {
  const std::lock_guard<std::mutex> lock(m_clusterings->mutex);
  return m_clusterings->made;
}

Error LodCharacter::setJpcSettings(const JpcSettings& jpc) {
  std::vector<JpcClip> prepared;
  for (const Clip& clip : m_clips) {
    if (cancelled(m_meshSettings.cancel))
      return Error(kCancelled);
    Result<JpcClip> clipPrepared = JpcClip::prepare(m_skeleton, clip, jpc);
    if (!clipPrepared)
      return Error("clip '" + clip.name + "': " + clipPrepared.message());
    prepared.push_back(std::move(clipPrepared).value());
  }
  m_prepared = std::move(prepared);
  m_jpc = jpc;
  return {};
}

Error LodCharacter::measureMotionError(LevelMotion& motion) const {
  if (motion.motionErrorExact)
    return {};
  assert(m_mesh && motion.mesh && motion.clips.size() == m_clips.size());
  double largest = 0.0;
  for (std::size_t c = 0; c < m_clips.size(); ++c) {
    Result<double> measured = m_deviation.measure(m_skeleton, *m_mesh, m_clips[c], motion.bones, *motion.mesh,
                                                  motion.clips[c], largest, m_meshSettings.cancel);
    if (!measured)
      return measured.error();
    largest = *measured;
  }
  motion.motionErrorCm = largest;
  motion.motionErrorExact = true;
  return {};
}

Result<MeshLod> LodCharacter::meshLodFor(const LevelMotion& motion) const {
  if (!motion.mesh)
    return Error("LOD: the character has no mesh");
  MeshLodSettings settings = m_meshSettings;
  if (settings.jointImportance.empty()) { // the joints' mesh importance, on the level's skeleton
    const std::vector<Joint>& joints = motion.bones.skeleton.joints;
    bool any = false;
    for (const Joint& joint : joints)
      any = any || m_jpc.meshImportanceFor(joint.name) != 1.0;
    if (any)
      for (const Joint& joint : joints)
        settings.jointImportance.push_back(static_cast<float>(m_jpc.meshImportanceFor(joint.name)));
  }
  return MeshLod::build(*motion.mesh, &motion.bones.skeleton, motion.clips, settings);
}

Result<LevelBuild> LodCharacter::build(double threshold, double meshRatio, int level) const {
  if (!(meshRatio > 0.0 && meshRatio <= 1.0))
    return Error("LOD: a mesh ratio must be in (0, 1]");
  Result<LevelMotion> motion = motionAt(threshold, level);
  if (!motion)
    return motion.error();
  LevelBuild out;
  out.motion = std::move(motion).value();
  if (out.motion.mesh) {
    Result<MeshLod> lod = meshLodFor(out.motion);
    if (!lod)
      return lod.error();
    out.mesh = lod->levelForRatio(meshRatio);
    if (cancelled(m_meshSettings.cancel)) // its errors may be unmeasured
      return Error(kCancelled);
  }
  return out;
}

} // namespace mlod
