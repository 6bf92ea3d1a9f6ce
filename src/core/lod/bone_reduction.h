#pragma once
// Bone reduction per LOD level: a joint that holds one pose, within the level's bound, in
// every clip the character plays is removed at that level; its children hang from its
// nearest active ancestor through the frozen transform, and its vertices are rebound to
// that ancestor with the frozen pose baked in. (Beyond the paper: JPC freezes a joint for
// the frames of a cluster, Ahn & Wohn section 4; a joint frozen for every frame of every
// clip needs no joint at all, and its skin no matrix of its own.)
//
// A joint j (not the root, not locked) is removed at threshold T when some frame k of the
// clips (taken one after another) has E_j(t, k) <= T_j for every frame t of every clip
// (E as JPC measures it, posture_error.h, cm·degrees; T_j the level's threshold or the
// joint's override), and its translation and scale are its rest values in every frame. The
// frozen pose is the k with the smallest largest error. Joints without a rotation channel
// hold their rest rotation and are removed at any threshold.
//
// Rebinding: a removed joint r under active ancestor a moves rigidly with a: its skinning
// matrix is palette(a) * B_r with B_r = bind(a) * F_r * inverseBind(r), F_r the frozen local
// transforms from a down to r. A vertex whose influences all end on one active joint gets
// position sum_i w_i B_i p: exact in every pose. A vertex that blends joints ending on
// different active joints gets the same weighted position, which is exact where the frozen
// poses equal the bind pose and an approximation elsewhere (its error is what the LOD set
// measures, lod_set.h).

#include "core/clip.h"
#include "core/error.h"
#include "core/jpc/jpc_settings.h"
#include "core/skeleton.h"
#include "core/skinned_mesh.h"

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <atomic>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace mlod {

struct BoneReduction {
  std::vector<std::uint8_t> removed;     // per joint of the full skeleton
  std::vector<int> activeAncestor;       // per joint: itself when active, else its nearest active ancestor
  std::vector<glm::quat> frozenRotation; // per joint: the local rotation a removed joint holds (rest elsewhere)
  std::vector<double> frozenError;       // per joint: the largest E(t, key) over the clips, cm·degrees (0 if active)
  std::vector<int> reducedIndex;         // per full joint: its index in `skeleton`, -1 when removed
  std::vector<int> fullIndex;            // per reduced joint: its full joint
  Skeleton skeleton;                     // the active joints, parents rewired, frozen transforms folded in

  int removedCount() const;
  bool identity() const { return removedCount() == 0; }
};

// The joints of `skeleton` that `clips` (all of them validating against it; at least one)
// hold frozen within `threshold` (cm·degrees, >= 0) at LOD level `level` of `settings`.
// Errors: invalid skeleton, clips, settings or threshold; kCancelled once `cancel`
// (core/cancel.h, may be null) is set, looked at per joint and per candidate key.
Result<BoneReduction> reduceBones(const Skeleton& skeleton, std::span<const Clip> clips, double threshold,
                                  const JpcSettings& settings = {}, int level = 0,
                                  const std::atomic<bool>* cancel = nullptr);

// What reduceBones() learns of each joint whatever the threshold, kept for later calls on the
// same skeleton and clips (a pixel budget's search reduces the bones at ten thresholds and
// more, lod_character.h): the joint's posture track over the clips, its errors from frame 0
// and from the frame farthest from it, and the frozen pose once found (or the largest
// threshold it was not found within). A call with the cache gives the same reduction, to the
// bit, as one without. The caller keeps one cache per (skeleton, clips); entries are checked
// against each joint's alpha and zero-length tolerance. Thread-safe (calls take turns).
class BoneReductionCache {
public:
  BoneReductionCache();
  ~BoneReductionCache();
  BoneReductionCache(const BoneReductionCache&) = delete;
  BoneReductionCache& operator=(const BoneReductionCache&) = delete;

  struct State; // bone_reduction.cpp
  State& state() const { return *m_state; } // reduceBones()'s

private:
  std::unique_ptr<State> m_state;
};

// The same through `cache` (may be null: as above).
Result<BoneReduction> reduceBones(const Skeleton& skeleton, std::span<const Clip> clips, double threshold,
                                  const JpcSettings& settings, int level, const std::atomic<bool>* cancel,
                                  BoneReductionCache* cache);

// `clip` (of the full skeleton) with every removed joint at its frozen rotation (a clip
// passed as an rvalue is changed in place, not copied).
Clip frozenClip(const BoneReduction& reduction, Clip clip);

// `clip` (of the full skeleton) on the reduced skeleton: each active joint's local transform
// is the frozen transforms of the removed joints above it (up to its active ancestor) times
// its own. Channels as in `clip`.
Clip reduceClip(const BoneReduction& reduction, const Skeleton& full, const Clip& clip);

// Per joint of `full`: B_r (above) for a removed joint r, the identity for an active one.
// rebindMesh() bakes with these.
std::vector<glm::mat4> bakeMatrices(const BoneReduction& reduction, const Skeleton& full);

// `mesh` (bound to the full skeleton) bound to the reduced one: influences on removed joints
// move to their active ancestors, positions and normals baked as above, weights merged and
// normalised (<= 4, sorted, exact sums).
SkinnedMesh rebindMesh(const BoneReduction& reduction, const Skeleton& full, const SkinnedMesh& mesh);

} // namespace mlod
