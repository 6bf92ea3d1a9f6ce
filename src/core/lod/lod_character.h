#pragma once
// A character with the clips it plays, prepared for building LOD levels in which motion and
// mesh are simplified together (issue 5, "co-built LOD set"): what one level plays and
// shows, and how far it strays from the original, in cm.
//
// A level at motion threshold E (cm·degrees) and mesh ratio r:
//  1. JPC clusters every clip at E (core/jpc/jpc.h): M'(t);
//  2. bone reduction at E (bone_reduction.h): joints frozen in every clip go, their skin is
//     rebound to their active ancestors;
//  3. the level's motion: M' with the removed joints at their frozen pose, on the reduced
//     skeleton;
//  4. the mesh LOD of the *rebound* mesh (mesh_lod.h), its collapse costs and errors in the
//     level's own animated poses, each joint's mesh importance (JointSettings) scaling the
//     cost of the vertices it moves.
// Motion error: the largest displacement of a skin vertex (of a joint, for a skeleton
// without mesh) between the original render (full skeleton, original clip, original mesh)
// and the level's full-resolution render, over every frame of every clip, cm. Mesh error:
// the level mesh's error (mesh_lod.h), cm. The two add up to a bound of the level's
// deviation from the original (triangle inequality) in every measured pose.

#include "core/clip.h"
#include "core/error.h"
#include "core/jpc/cluster_set.h"
#include "core/jpc/jpc.h"
#include "core/jpc/jpc_settings.h"
#include "core/lod/bone_reduction.h"
#include "core/lod/skin_deviation.h"
#include "core/mesh/mesh_lod.h"
#include "core/skeleton.h"
#include "core/skinned_mesh.h"

#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <tuple>
#include <vector>

namespace mlod {

// What one level plays: its motion on the reduced skeleton, and the skin it moves.
struct LevelMotion {
  double threshold = 0.0; // E, cm·degrees
  BoneReduction bones;
  std::vector<ClusterSet> clusters; // per clip, on the full skeleton
  std::vector<Clip> clips;          // per clip, on bones.skeleton
  std::optional<SkinnedMesh> mesh;  // the full-resolution mesh rebound to bones.skeleton (when there is a mesh)
  double motionErrorCm = 0.0;       // see above; an upper bound of it while !motionErrorExact
  bool motionErrorExact = true;     // false: motionAt(..., MotionError::Bound) took the bound alone
  // 100 x clustered joint-frames / (clusterable joints x frames), every clip.
  double simplifiedPercent = 0.0;
};

// One level, built.
struct LevelBuild {
  LevelMotion motion;
  std::optional<MeshLodLevel> mesh; // the simplified rebound mesh and its errors (when there is a mesh)
  double meshErrorCm() const { return mesh ? mesh->maxErrorCm : 0.0; }
  double deviationCm() const { return motion.motionErrorCm + meshErrorCm(); }
};

class LodCharacter {
public:
  // `mesh` may be null (a skeleton alone); `clips` (at least one, of `skeleton`) are every
  // clip the character plays (its own and mapped ones, motion_mapping.h). Errors: invalid
  // skeleton, mesh, clips or settings; `cancel` set (kCancelled).
  // `cancel` (core/cancel.h, may be null; else it replaces meshSettings.cancel) is kept: once
  // it is set, prepare(), motionAt(), meshLodFor() and build() stop between clips, joints,
  // frames and poses and return kCancelled. It must outlive the LodCharacter.
  static Result<LodCharacter> prepare(const Skeleton& skeleton, const SkinnedMesh* mesh, std::span<const Clip> clips,
                                      const JpcSettings& jpc = {}, const MeshLodSettings& meshSettings = {},
                                      const std::atomic<bool>* cancel = nullptr);

  const Skeleton& skeleton() const { return m_skeleton; }
  const std::vector<Clip>& clips() const { return m_clips; }
  const std::optional<SkinnedMesh>& mesh() const { return m_mesh; }
  // The radius (cm) of the sphere about the root joint that holds the posed mesh (the
  // joints without a mesh) in every frame of every clip.
  double boundingRadiusCm() const { return m_radius; }

  // Steps 1-3 at threshold E (>= 0) of LOD level `level` (for per-joint overrides).
  // Every call's clustering counts against one work budget (core/jpc/work_budget.h, the
  // limit of setWorkLimit(), kMaxJpcWork by default): a pixel budget's search tries many
  // thresholds, so a clip that one simplify takes seconds for could keep it busy for hours.
  // Past it, this and every later call is refused, naming the limit.
  Result<LevelMotion> motionAt(double threshold, int level = 0) const;
  // What the motion error of a level costs: measured (to the bit, skin_deviation.h), or an
  // upper bound of it from the skinning palettes alone (no frame skinned; worth it where
  // the error is float noise, at E = 0, and only a bound is compared).
  enum class MotionError { Exact, Bound };
  Result<LevelMotion> motionAt(double threshold, int level, MotionError measure) const;
  // Measures the error of a motion that motionAt() bounded (nothing when it is exact). Errors:
  // kCancelled.
  Error measureMotionError(LevelMotion& motion) const;
  // The work every motionAt() of this character may spend together, from now on.
  void setWorkLimit(std::int64_t units) { m_work = std::make_shared<JpcWorkBudget>(units); }
  // Step 4's progressive mesh for a level's motion (an error without a mesh).
  Result<MeshLod> meshLodFor(const LevelMotion& motion) const;

  // The same character under other JPC settings (a pixel budget's cache after a joint edit,
  // lod_budget_cache.h): the clips' JPC tracks prepared again, the rest kept, clusterings
  // whose key is unchanged still reused (below). Errors: as prepare()'s for the settings.
  Error setJpcSettings(const JpcSettings& jpc);
  const JpcSettings& jpcSettings() const { return m_jpc; }
  const MeshLodSettings& meshSettings() const { return m_meshSettings; }
  // The flag that stops the work from now on (core/cancel.h, may be null; see prepare()).
  void setCancel(const std::atomic<bool>* cancel) { m_meshSettings.cancel = cancel; }
  // note: every joint clustering motionAt() makes is kept, keyed by what decides it (the
  // clip, the joint, T_j, alpha_j, the mode and the zero-length tolerance; the joint's
  // track is the clip's, fixed for the character), and reused by every later call that needs
  // it, whatever the level and threshold asked: a search that tries a threshold twice, or
  // again after one joint's settings changed, clusters only what it has not clustered.
  // Copies of the character share them. Joint clusterings made so far (not reused):
  std::int64_t jointsClustered() const;
  // A whole level: motion at E, mesh at ratio r in (0, 1].
  Result<LevelBuild> build(double threshold, double meshRatio, int level = 0) const;

private:
  struct ClusteringKey {
    int clip = 0, joint = 0;
    double threshold = 0.0, alpha = 0.0, zeroLength = 0.0;
    JpcMode mode = JpcMode::Greedy;
    friend auto operator<=>(const ClusteringKey&, const ClusteringKey&) = default;
  };
  struct Clusterings {
    std::mutex mutex;
    std::map<ClusteringKey, JointClustering> kept;
    std::int64_t made = 0;
  };
  // Every joint of clip `c` at `level`, threshold E: kept clusterings, the others made (in
  // parallel) and kept unless the run was cancelled or ran out of work.
  std::vector<JointClustering> clusterClip(std::size_t c, int level, double threshold) const;

  Skeleton m_skeleton;
  std::optional<SkinnedMesh> m_mesh;
  std::vector<Clip> m_clips;
  std::vector<JpcClip> m_prepared;
  JpcSettings m_jpc;
  MeshLodSettings m_meshSettings; // its cancel is the character's
  double m_radius = 0.0;
  SkinDeviation m_deviation;                                                 // of m_mesh, when it is skinned
  std::shared_ptr<JpcWorkBudget> m_work = std::make_shared<JpcWorkBudget>(); // shared by copies
  std::shared_ptr<Clusterings> m_clusterings = std::make_shared<Clusterings>(); // shared by copies
  // What bone reduction learns per joint whatever the threshold (bone_reduction.h): the
  // skeleton and clips are the character's for good. Shared by copies.
  std::shared_ptr<BoneReductionCache> m_boneFacts = std::make_shared<BoneReductionCache>();
};

} // namespace mlod
