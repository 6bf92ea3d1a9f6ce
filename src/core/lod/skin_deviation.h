#pragma once
// The motion error of a LOD level (lod_character.h): the largest displacement of a skin
// vertex between the original render (full skeleton, original clip, original mesh) and the
// level's full-resolution render (reduced skeleton, the level's clip, the rebound mesh,
// bone_reduction.h), over every frame, cm — the same number, to the bit, as skinning both
// meshes in every frame (skinPositions()) and taking the largest float distance, at a
// fraction of the cost: a pixel budget's search measures a dozen levels of a 4,500-frame
// clip.
//
// note: a frame is skinned only when a bound says it may raise the maximum. Per joint j of
// the full skeleton, D_j = P'_a B_j - P_j is how far the level moves what j carries (P the
// skinning palettes, a the active joint that j's skin is rebound to, B_j its bake matrix):
// a vertex moves by sum_i w_i D_i p, so by at most max_i |D_i c| + |D_i|_F rho over a small
// group of j's bind positions (centre c, radius rho) that holds p. A vertex that blends
// joints rebound to different active joints (an approximation there, bone_reduction.h)
// moves further by at most how far those joints turn apart times how far its baked position
// lies from each part's (skin_deviation.cpp). The bound covers the float rounding of both
// renders with a wide margin (1e-5 of the largest skinned coordinate, ~80 float ulps).
// Frames are skinned in order of falling bound until the next bound cannot reach the
// largest error found: on the candidates of a pixel budget, a few to a few hundred of 4,511.

#include "core/clip.h"
#include "core/error.h"
#include "core/lod/bone_reduction.h"
#include "core/skeleton.h"
#include "core/skinned_mesh.h"

#include <atomic>
#include <glm/glm.hpp>
#include <vector>

namespace mlod {

class SkinDeviation {
public:
  SkinDeviation() = default;
  // `mesh`: skinned and valid for the skeleton it is measured with.
  explicit SkinDeviation(const SkinnedMesh& mesh);

  // max(floor, the largest float distance between skinPositions() of `mesh` on `skeleton`
  // playing `clip` and of `levelMesh` (rebindMesh(bones, skeleton, mesh)) on bones.skeleton
  // playing `levelClip` (reduceClip() of the level's motion: the same frames)), cm, over every
  // frame and vertex. `mesh` is the one this was made from. Errors: kCancelled once `cancel`
  // (core/cancel.h, may be null) is set, looked at per frame.
  Result<double> measure(const Skeleton& skeleton, const SkinnedMesh& mesh, const Clip& clip,
                         const BoneReduction& bones, const SkinnedMesh& levelMesh, const Clip& levelClip, double floor,
                         const std::atomic<bool>* cancel = nullptr) const;

  // At least measure() (the same arguments): an upper bound from the skinning palettes
  // alone, no frame skinned; max(floor, ...) too.
  Result<double> bound(const Skeleton& skeleton, const SkinnedMesh& mesh, const Clip& clip, const BoneReduction& bones,
                       const SkinnedMesh& levelMesh, const Clip& levelClip, double floor,
                       const std::atomic<bool>* cancel = nullptr) const;

  // A few bind positions of the vertices one joint influences.
  struct Group {
    glm::dvec3 centre{0.0};
    double radius = 0.0; // cm: every position of the group lies within it of the centre
  };

private:
  // Per frame: at least the largest distance measure() finds in that frame.
  Result<std::vector<double>> reachPerFrame(const Skeleton& skeleton, const SkinnedMesh& mesh, const Clip& clip,
                                            const BoneReduction& bones, const SkinnedMesh& levelMesh,
                                            const Clip& levelClip, const std::atomic<bool>* cancel) const;

  std::vector<std::vector<Group>> m_groups; // per joint: its vertices (weight > 0), in groups
  double m_extent = 0.0;                    // the largest |bind position|, cm
};

} // namespace mlod
