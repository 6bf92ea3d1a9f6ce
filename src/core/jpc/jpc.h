#pragma once
// Joint posture clustering (JPC) of a clip: Ahn & Wohn, "Motion Level-of-Detail: A
// Simplification Method on Crowd Scene", section 4, as docs/architecture.md section 4 makes it
// precise. Per joint, runs of consecutive frames whose postures all stay within an error
// threshold of one key posture become clusters; inside a cluster the joint is frozen at
// its key posture.
//
// The pieces, one file each: posture_error.h (eqs. (1)-(6)), clustering_table.h (STEP 1,
// banded), greedy_clustering.h (STEPs 2-5), optimal_clustering.h (beyond the paper),
// key_posture.h (eq. (7), STEP 6), simplified_motion.h (M'(t) and its error in cm).
//
// Units: thresholds and errors E in cm·degrees, alpha in cm, positions in cm.
// Guarantee, for every clustered frame t of joint j: E_j(t, key) <= T_j.

#include "core/clip.h"
#include "core/error.h"
#include "core/jpc/cluster_set.h"
#include "core/jpc/jpc_settings.h"
#include "core/jpc/posture_error.h"
#include "core/jpc/work_budget.h"
#include "core/skeleton.h"

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <string>
#include <vector>

namespace mlod {

// The clusters of one joint.
struct JointClustering {
  std::vector<Cluster> clusters; // sorted, disjoint, >= 3 frames each, key inside
  int clusteredFrames = 0;
  double maxError = 0.0;        // max E(t, key) over the clustered frames; 0 without clusters
  std::int64_t evaluations = 0; // exact error evaluations spent (statistic)
  std::int64_t work = 0;        // JpcWorkBudget units spent (work_budget.h)
};

// Clusters one joint at threshold T (cm·degrees, >= 0): the clustering table, the ranges
// chosen by `mode`, the keys by eq. (7). Deterministic. On the 2,752-frame CMU clip it
// takes 0.2 to 7 ms per joint (bench_jpc, BM_ClusterJointSlowest). `budget` (may be null)
// is charged with the work; once it is past its limit the joint stops where it is, with
// the clusters found so far (the caller checks the budget and drops the result).
JointClustering clusterJoint(const JointTrack& track, double threshold, JpcMode mode,
                             JpcWorkBudget* budget = nullptr);

// Where a JpcClip keeps the error tracks of its joints (JointTrack: (56 + 36 x directions)
// bytes per frame each, about 2.3 times the decoded clip for all joints of a CMU skeleton).
enum class JpcTracks {
  Kept,     // built by prepare() and kept: re-clustering a joint costs no track (the editor)
  OnDemand, // built when a joint is clustered and dropped after: one track per thread at a
            // time (the command line, long clips); the clip must outlive the JpcClip
};

// The most work JPC takes on for one clip, refused by JpcClip::prepare() before any
// clustering with the limit named: the key-posture search grows faster than the length
// of a cluster (about m^1.8 on a slow wobble that stays within the threshold: 100,000
// frames took 5.5 s per joint here, 200,000 frames 43 s), so a clip whose joints might
// hold one posture for hours could run for hours. 100,000 frames is 14 minutes at 120 fps;
// 4 million joint-frames is 18 minutes of a 31-joint CMU skeleton at 120 fps.
inline constexpr int kMaxJpcFrames = 100'000;
inline constexpr std::int64_t kMaxJpcJointFrames = 4'000'000;

// What JPC needs from one clip, prepared once for any number of thresholds: the error
// tracks of every clusterable joint (those with a rotation channel) that is not locked.
// Re-clustering one joint after an edit of its threshold is clusterJoint(track(j), T, mode).
class JpcClip {
public:
  // Checks `settings` (unknown joint names, negative or NaN alpha ...) and `clip` against
  // `skeleton`, and the work limits (kMaxJpcFrames, kMaxJpcJointFrames); bad input is an
  // Error with a message. With JpcTracks::OnDemand the JpcClip
  // refers to `clip`, which must outlive it.
  static Result<JpcClip> prepare(const Skeleton& skeleton, const Clip& clip, const JpcSettings& settings,
                                 JpcTracks tracks = JpcTracks::Kept);

  int jointCount() const { return static_cast<int>(m_joints.size()); }
  int frameCount() const { return m_frameCount; }
  const JpcSettings& settings() const { return m_settings; }
  const std::string& jointName(int joint) const { return m_joints[static_cast<std::size_t>(joint)].name; }
  // The joint carries a rotation channel in the clip (docs/architecture.md section 4).
  bool clusterable(int joint) const { return m_joints[static_cast<std::size_t>(joint)].clusterable; }
  bool locked(int joint) const { return m_joints[static_cast<std::size_t>(joint)].locked; }
  int clusterableCount() const;
  bool tracksKept() const { return m_clip == nullptr; }
  // The joint's error track; only for clusterable joints that are not locked, and only
  // with JpcTracks::Kept.
  const JointTrack& track(int joint) const;
  // The joint's error track built anew (either way of keeping tracks); the same bits as
  // track(joint). Only for clusterable joints that are not locked.
  JointTrack buildTrack(int joint) const;
  // Bytes of buildTrack(joint) (0 for a joint without a track).
  std::size_t trackBytes(int joint) const;
  // T_j at `level` whose threshold is `levelThreshold` (cm·degrees).
  double threshold(int joint, int level, double levelThreshold) const;

  // Clusters one joint at `level` (no clusters for locked and unclusterable joints).
  // `budget` as in mlod::clusterJoint().
  JointClustering clusterJoint(int joint, int level, double levelThreshold, JpcWorkBudget* budget = nullptr) const;
  // Clusters one joint at every level (level i at levelThresholds[i]) from one track:
  // what clusterJoint(joint, i, levelThresholds[i]) gives, level by level. `budget` as in
  // mlod::clusterJoint().
  std::vector<JointClustering> clusterJointLevels(int joint, std::span<const double> levelThresholds,
                                                  JpcWorkBudget* budget = nullptr) const;
  // Clusters every joint at one level, on up to `threads` threads (0 = all hardware
  // threads). One entry per joint. Once `cancel` (core/cancel.h, may be null) is set, the
  // joints not yet started are left without clusters: the caller checks the flag and drops
  // the result. Likewise once `budget` (may be null) is exhausted: the caller refuses.
  std::vector<JointClustering> cluster(int level, double levelThreshold, int threads = 0,
                                       const std::atomic<bool>* cancel = nullptr, JpcWorkBudget* budget = nullptr) const;

private:
  struct JointEntry {
    std::string name;
    bool clusterable = false;
    bool locked = false;
    JointGeometry geometry;
    JointTrack track; // empty with JpcTracks::OnDemand
  };
  JpcSettings m_settings;
  int m_frameCount = 0;
  std::vector<JointEntry> m_joints;
  const Clip* m_clip = nullptr; // with JpcTracks::OnDemand: the clip the tracks come from
};

// Table 1 of the paper and the fidelity a technical artist reads, for one joint.
struct JointMetrics {
  bool clusterable = false;
  bool locked = false;
  double threshold = 0.0; // T_j, cm·degrees
  int clusters = 0;
  int clusteredFrames = 0;
  double simplifiedPercent = 0.0; // 100 x clustered frames / frames
  double maxError = 0.0;          // max E(t, key) over clustered frames, cm·degrees
};

// One LOD level of a clip.
struct JpcLevelResult {
  double threshold = 0.0; // the level's threshold, cm·degrees
  ClusterSet clusters;
  std::vector<JointMetrics> joints; // per skeleton joint
  // 100 x clustered joint-frames / (clusterable joints x frames): the paper's Table 1.
  double simplifiedPercent = 0.0;
  int clusterCount = 0;
  double maxError = 0.0;                // over every joint, cm·degrees
  double maxJointPositionErrorCm = 0.0; // forward kinematics of M' against M, every joint and frame
  double meanJointPositionErrorCm = 0.0;
};

// Clusters `clip` at each threshold of `levelThresholds` (level i gets threshold i and
// the per-joint overrides of level i) and measures the result. Work is spread over up to
// `threads` threads (0 = all hardware threads); the result does not depend on it.
// Errors: invalid settings, thresholds or clip; a clip whose clustering needs more than
// `workLimit` units of work (work_budget.h: error evaluations, every joint and threshold
// together), naming the limit and the clip: whether a clip is refused does not depend on
// threads or timing.
// Memory, beyond the clip and the results: the joint positions of the clip (12 bytes per
// joint and frame) and the working buffers of the joints being clustered (JpcTracks::
// OnDemand), with as many joints at once as fit in kSimplifyWorkingBytes or half the
// decoded clip, whichever is larger (at least one joint; fewer threads if need be).
inline constexpr std::size_t kSimplifyWorkingBytes = std::size_t{16} << 20; // 16 MiB

Result<std::vector<JpcLevelResult>> simplifyClip(const Skeleton& skeleton, const Clip& clip,
                                                 const JpcSettings& settings, std::span<const double> levelThresholds,
                                                 int threads = 0, std::int64_t workLimit = kMaxJpcWork);

// Gathers one level's clusters (one JointClustering per joint, from JpcClip::cluster())
// into a ClusterSet with its metrics; the joint-position error is forward kinematics of
// M' against `clip`. `originalPositions` as in jointPositionError().
JpcLevelResult measureLevel(const JpcClip& prepared, const Skeleton& skeleton, const Clip& clip, int level,
                            double levelThreshold, std::vector<JointClustering> joints,
                            std::span<const glm::vec3> originalPositions = {});

} // namespace mlod
