// Joint posture clustering, Ahn & Wohn section 4; docs/architecture.md section 4.
#include "core/jpc/jpc.h"
#include "core/cancel.h"

#include "core/jpc/clustering_table.h"
#include "core/jpc/greedy_clustering.h"
#include "core/jpc/key_posture.h"
#include "core/jpc/optimal_clustering.h"
#include "core/jpc/parallel_for.h"
#include "core/jpc/simplified_motion.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <string>
#include <thread>

namespace mlod {

JointClustering clusterJoint(const JointTrack& track, double threshold, JpcMode mode, JpcWorkBudget* budget) {
  assert(threshold >= 0.0 && std::isfinite(threshold));
  JointClustering out;
  if (track.frameCount() < kMinClusterFrames)
    return out;
  const bool optimal = mode == JpcMode::Optimal;
  const ClusteringTable table(track, threshold, optimal ? TableRows::EndsAndStarts : TableRows::EndsOnDemand);
  const std::vector<FrameRange> ranges =
      optimal ? optimalRanges(table.rowStarts(), table.rowEnds())
              : greedyRanges(track.frameCount(), [&](int ref) { return table.rowEnd(ref); });
  out.evaluations = table.evaluations();
  out.work = table.evaluations() * kExactEvaluationUnits;
  if (budget && !budget->spend(out.work))
    return out;
  out.clusters.reserve(ranges.size());
  for (const FrameRange& range : ranges) {
    const KeyPosture key = keyPosture(track, range, threshold, &table, budget);
    out.evaluations += key.evaluations;
    out.work += key.work;
    if (key.stopped)
      return out;
    // Every range has a row that holds it: greedy's own first row, optimal's window key.
    assert(key.key >= 0);
    if (key.key < 0)
      continue;
    out.clusters.push_back({range.first, range.last, key.key});
    out.clusteredFrames += range.length();
    out.maxError = std::max(out.maxError, key.maxError);
  }
  return out;
}

Result<JpcClip> JpcClip::prepare(const Skeleton& skeleton, const Clip& clip, const JpcSettings& settings,
                                 JpcTracks tracks) {
  if (Error error = skeleton.validate())
    return Error("the skeleton is invalid: " + error.message());
  if (Error error = clip.validate(skeleton))
    return error;
  if (Error error = settings.validate(skeleton))
    return error;
  // (callers name the clip)
  if (clip.frameCount > kMaxJpcFrames)
    return Error(std::to_string(clip.frameCount) + " frames are more than joint posture clustering takes (at most " +
                 std::to_string(kMaxJpcFrames) + " frames per clip): trim or split the clip");
  std::int64_t jointFrames = 0; // of the joints that will be clustered
  for (int j = 0; j < skeleton.jointCount(); ++j)
    if (clip.hasRotation[static_cast<std::size_t>(j)] &&
        !settings.lockedFor(skeleton.joints[static_cast<std::size_t>(j)].name))
      jointFrames += clip.frameCount;
  if (jointFrames > kMaxJpcJointFrames)
    return Error(std::to_string(jointFrames) + " rotating joint-frames are more than joint posture clustering takes (at most " +
                 std::to_string(kMaxJpcJointFrames) + " per clip): trim the clip or lock joints");
  JpcClip out;
  out.m_settings = settings;
  out.m_frameCount = clip.frameCount;
  out.m_clip = &clip;
  std::vector<JointGeometry> geometry = jointGeometry(skeleton, settings.zeroLength);
  out.m_joints.resize(static_cast<std::size_t>(skeleton.jointCount()));
  for (int j = 0; j < skeleton.jointCount(); ++j) {
    JointEntry& entry = out.m_joints[static_cast<std::size_t>(j)];
    entry.name = skeleton.joints[static_cast<std::size_t>(j)].name;
    entry.clusterable = clip.hasRotation[static_cast<std::size_t>(j)] != 0;
    entry.locked = settings.lockedFor(entry.name);
    entry.geometry = std::move(geometry[static_cast<std::size_t>(j)]);
    if (tracks == JpcTracks::Kept && entry.clusterable && !entry.locked)
      entry.track = out.buildTrack(j);
  }
  if (tracks == JpcTracks::Kept)
    out.m_clip = nullptr;
  return out;
}

int JpcClip::clusterableCount() const {
  return static_cast<int>(
      std::count_if(m_joints.begin(), m_joints.end(), [](const JointEntry& entry) { return entry.clusterable; }));
}

const JointTrack& JpcClip::track(int joint) const {
  assert(clusterable(joint) && !locked(joint) && tracksKept());
  return m_joints[static_cast<std::size_t>(joint)].track;
}

JointTrack JpcClip::buildTrack(int joint) const {
  assert(clusterable(joint) && !locked(joint));
  const JointEntry& entry = m_joints[static_cast<std::size_t>(joint)];
  if (!m_clip)
    return entry.track;
  const std::span<const glm::quat> rotations(&m_clip->rotations[m_clip->index(joint, 0)],
                                             static_cast<std::size_t>(m_frameCount));
  return JointTrack(entry.geometry, m_settings.alphaFor(entry.name), rotations);
}

std::size_t JpcClip::trackBytes(int joint) const {
  if (!clusterable(joint) || locked(joint))
    return 0;
  return JointTrack::bytesFor(m_frameCount,
                              static_cast<int>(m_joints[static_cast<std::size_t>(joint)].geometry.directions.size()));
}

double JpcClip::threshold(int joint, int level, double levelThreshold) const {
  return m_settings.thresholdFor(jointName(joint), level, levelThreshold);
}

JointClustering JpcClip::clusterJoint(int joint, int level, double levelThreshold, JpcWorkBudget* budget) const {
  if (!clusterable(joint) || locked(joint))
    return {};
  const double jointThreshold = threshold(joint, level, levelThreshold);
  if (tracksKept())
    return mlod::clusterJoint(track(joint), jointThreshold, m_settings.mode, budget);
  return mlod::clusterJoint(buildTrack(joint), jointThreshold, m_settings.mode, budget);
}

std::vector<JointClustering> JpcClip::clusterJointLevels(int joint, std::span<const double> levelThresholds,
                                                         JpcWorkBudget* budget) const {
  std::vector<JointClustering> out(levelThresholds.size());
  if (!clusterable(joint) || locked(joint))
    return out;
  JointTrack built;
  if (!tracksKept())
    built = buildTrack(joint);
  const JointTrack& jointTrack = tracksKept() ? track(joint) : built;
  for (std::size_t level = 0; level < levelThresholds.size() && !exhausted(budget); ++level)
    out[level] = mlod::clusterJoint(jointTrack, threshold(joint, static_cast<int>(level), levelThresholds[level]),
                                    m_settings.mode, budget);
  return out;
}

std::vector<JointClustering> JpcClip::cluster(int level, double levelThreshold, int threads,
                                              const std::atomic<bool>* cancel, JpcWorkBudget* budget) const {
  std::vector<JointClustering> out(m_joints.size());
  parallelFor(jointCount(), threads, [&](int j) {
    if (!cancelled(cancel) && !exhausted(budget)) // looked at per joint
      out[static_cast<std::size_t>(j)] = clusterJoint(j, level, levelThreshold, budget);
  });
  return out;
}

JpcLevelResult measureLevel(const JpcClip& prepared, const Skeleton& skeleton, const Clip& clip, int level,
                            double levelThreshold, std::vector<JointClustering> joints,
                            std::span<const glm::vec3> originalPositions) {
  assert(static_cast<int>(joints.size()) == prepared.jointCount());
  JpcLevelResult out;
  out.threshold = levelThreshold;
  out.clusters.frameCount = prepared.frameCount();
  out.clusters.joints.resize(joints.size());
  out.joints.resize(joints.size());
  long long clusteredJointFrames = 0;
  for (int j = 0; j < prepared.jointCount(); ++j) {
    JointClustering& clustering = joints[static_cast<std::size_t>(j)];
    JointMetrics& metrics = out.joints[static_cast<std::size_t>(j)];
    metrics.clusterable = prepared.clusterable(j);
    metrics.locked = prepared.locked(j);
    metrics.threshold = prepared.threshold(j, level, levelThreshold);
    metrics.clusters = static_cast<int>(clustering.clusters.size());
    metrics.clusteredFrames = clustering.clusteredFrames;
    metrics.simplifiedPercent = 100.0 * clustering.clusteredFrames / prepared.frameCount();
    metrics.maxError = clustering.maxError;
    clusteredJointFrames += clustering.clusteredFrames;
    out.clusterCount += metrics.clusters;
    out.maxError = std::max(out.maxError, metrics.maxError);
    out.clusters.joints[static_cast<std::size_t>(j)] = std::move(clustering.clusters);
  }
  const double jointFrames = static_cast<double>(prepared.clusterableCount()) * prepared.frameCount();
  out.simplifiedPercent = jointFrames > 0.0 ? 100.0 * static_cast<double>(clusteredJointFrames) / jointFrames : 0.0;
  const PositionError position = jointPositionError(skeleton, clip, out.clusters, originalPositions);
  out.maxJointPositionErrorCm = position.maxCm;
  out.meanJointPositionErrorCm = position.meanCm;
  return out;
}

namespace {
// The clustering's working buffers besides the track, per frame, at most: the table's
// step bound, ends and starts (16 bytes), the optimal mode's best covers and choices (12)
// and a key posture over a cluster as long as the clip (pivot errors, bounds, sort order
// and prefix sums: 7 x 8 bytes; 8 landmark rows and the nearest: 36; survivors: 16).
constexpr std::size_t kClusteringBytesPerFrame = 160;

// Threads for simplifyClip(): as many joints at once as their working buffers fit in the
// larger of kSimplifyWorkingBytes and half the decoded clip.
int clusteringThreads(const JpcClip& jpc, const Clip& clip, int threads) {
  if (threads <= 0)
    threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::size_t largest = 0;
  for (int j = 0; j < jpc.jointCount(); ++j)
    largest = std::max(largest, jpc.trackBytes(j));
  if (largest == 0)
    return threads;
  const std::size_t perJoint = largest + kClusteringBytesPerFrame * static_cast<std::size_t>(jpc.frameCount());
  const std::size_t decoded =
      clip.rotations.size() * sizeof(glm::quat) + (clip.translations.size() + clip.scales.size()) * sizeof(glm::vec3);
  const std::size_t budget = std::max(kSimplifyWorkingBytes, decoded / 2);
  return static_cast<int>(std::clamp<std::size_t>(budget / perJoint, 1, static_cast<std::size_t>(threads)));
}
} // namespace

Result<std::vector<JpcLevelResult>> simplifyClip(const Skeleton& skeleton, const Clip& clip,
                                                 const JpcSettings& settings, std::span<const double> levelThresholds,
                                                 int threads, std::int64_t workLimit) {
  for (std::size_t level = 0; level < levelThresholds.size(); ++level)
    if (Error error = validateThreshold(levelThresholds[level], levelThresholds.size() == 1
                                                                    ? std::string("threshold")
                                                                    : "threshold " + std::to_string(level + 1)))
      return error;
  Result<JpcClip> prepared = JpcClip::prepare(skeleton, clip, settings, JpcTracks::OnDemand);
  if (!prepared)
    return prepared.error();
  const JpcClip& jpc = *prepared;
  const int levels = static_cast<int>(levelThresholds.size());
  const int joints = jpc.jointCount();
  // Every joint is a task that builds its track once and clusters every level with it.
  std::vector<std::vector<JointClustering>> clustered(static_cast<std::size_t>(levels),
                                                      std::vector<JointClustering>(static_cast<std::size_t>(joints)));
  JpcWorkBudget budget(workLimit);
  parallelFor(joints, clusteringThreads(jpc, clip, threads), [&](int joint) {
    if (budget.exhausted())
      return;
    std::vector<JointClustering> byLevel = jpc.clusterJointLevels(joint, levelThresholds, &budget);
    for (std::size_t level = 0; level < byLevel.size(); ++level)
      clustered[level][static_cast<std::size_t>(joint)] = std::move(byLevel[level]);
  });
  if (budget.exhausted())
    return Error(workLimitMessage(clip.name, budget, "joint posture clustering",
                                  "per clip, every joint and threshold together",
                                  "trim the clip, lock joints or lower the threshold"));
  const std::vector<glm::vec3> original = jointPositions(skeleton, clip);
  std::vector<JpcLevelResult> out(static_cast<std::size_t>(levels));
  parallelFor(levels, threads, [&](int level) {
    const std::size_t l = static_cast<std::size_t>(level);
    out[l] = measureLevel(jpc, skeleton, clip, level, levelThresholds[l], std::move(clustered[l]), original);
  });
  return out;
}

} // namespace mlod
