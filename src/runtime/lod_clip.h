#pragma once
// A clip as the runtime plays it at one LOD level (docs/architecture.md section 5; Ahn & Wohn,
// "Motion Level-of-Detail", section 4): per joint, its clusters (runs of frames frozen at
// one key posture, with the key's local matrix precomputed), the rotations of the frames
// outside clusters, and the translation and scale tracks of the joints that animate them
// (the root's translation above all). A clip built without clusters is "full detail":
// the same data, the same evaluator.
//
// Time: frames are uniform, frame i plays at i / fps seconds. Between frames, rotations are
// normalised-lerped (the shorter way: stored rotations are sign-aligned at build time) and
// translations and scales lerped. A "frame position" is time x fps, in frames.
// Lengths are in cm. Immutable once built; any number of characters share one.
//
// What a cluster changes: a joint j with cluster [first, last] holds the key frame's
// rotation at every frame of the cluster, so at frame positions f in [first, last] its
// rotation is constant; this is M'(t) of the paper. Translations and scales are never
// clustered, so a joint is *frozen* (its whole local matrix constant) only inside a
// cluster and when its translation and scale tracks are constant.
//
// Unfreeze blending (docs/architecture.md section 5): when a cluster [first, last] of a joint ends
// before the clip does, its rotation jumps within one frame from the key to the next
// frame's. With blendFrames = N > 0 the jump is spread over N frames. At the whole frames k
// of the window [last, last + N) the joint shows
//     V(k) = nlerp(identity, D, 1 - (k - last) / N) * S(k),
// where S(k) is M'(k) except that frame `last` reads its original rotation q(last) instead
// of the key, and D = key * q(last)^-1: the cluster's own error at its last frame. Between
// whole frames f in [i0, i0 + 1) with i0 in the window, the joint shows the nlerp of V(i0)
// and V(i0 + 1) (V(last + N) = M'(last + N)). It equals the key at f = last and M'(f) from
// f = last + N on, and differs from M'(f) inside by about the angle of D at most, an error
// M' already makes inside the cluster (the joint stays within the level's joint-position
// fidelity); each frame it moves by the original motion plus 1/N of that angle. Windows of
// consecutive clusters that overlap compose (older offsets outermost). The window depends
// on the clip, N and the frame alone, so the per-frame plans hold it ready-made: a joint
// in a window is sampled like any other (its two rotations are V(i0) and V(i0 + 1)). A
// clip's plans are made for one N (blendFrames()).

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <new>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace mlod {

// The most frames of unfreeze and level-change blending (LodClipSource::blendFrames,
// LodClip::setBlendFrames(), PoseEvaluatorJob::blendFrames, Crowd and the CLI's
// --blend-frames).
inline constexpr int kMaxBlendFrames = 10000;

// Storage aligned to 64 bytes (a cache line): per-frame plans start on a line.
template <typename T> struct CacheLineAllocator {
  using value_type = T;
  CacheLineAllocator() = default;
  template <typename U> CacheLineAllocator(const CacheLineAllocator<U>&) {}
  T* allocate(std::size_t n) { return static_cast<T*>(::operator new(n * sizeof(T), std::align_val_t{64})); }
  void deallocate(T* p, std::size_t) { ::operator delete(p, std::align_val_t{64}); }
  template <typename U> bool operator==(const CacheLineAllocator<U>&) const { return true; }
};

// One cluster of a joint: inclusive frames [first, last], frozen at frame `key`'s rotation.
struct LodCluster {
  std::int32_t first = 0;
  std::int32_t last = 0;
  std::int32_t key = 0;
};

// What a LodClip is built from: plain arrays (the core's builder fills them from a Clip and
// a ClusterSet; an engine's asset pipeline can fill them from its own types).
struct LodClipSource {
  double fps = 30.0;          // frames per second, finite, > 0
  std::int32_t frameCount = 0; // >= 1
  std::int32_t jointCount = 0; // >= 1, <= 32767
  bool looping = false;       // wraps in the runtime (period: frameCount - 1 frames)
  // Joint-major tracks, [joint * frameCount + frame]: local rotations (unit quaternions),
  // translations (cm) and scales. A joint whose track holds one value throughout is static
  // in that channel; joints without a channel in the source simply hold their rest value.
  std::span<const glm::quat> rotations;
  std::span<const glm::vec3> translations;
  std::span<const glm::vec3> scales;
  // The clusters of every joint, joint after joint; joint j's are
  // clusters[clusterBegin[j] .. clusterBegin[j + 1]), sorted and disjoint, each >= 3 frames
  // with its key inside. clusterBegin has jointCount + 1 entries, or none (no clusters).
  std::span<const LodCluster> clusters;
  std::span<const std::uint32_t> clusterBegin;
  // Frames of unfreeze blending the plans are made for, [0, kMaxBlendFrames] (0 = none: M'(t)).
  int blendFrames = 0;
};

class LodClip {
public:
  // How one joint's rotation is read for the frames i0 in [first, last] (i0 = the frame
  // before the frame position; see framePosition()).
  struct Segment {
    std::int32_t first = 0;   // i0 range, inclusive
    std::int32_t last = 0;
    std::int32_t cluster = -1; // frozen: the cluster (index in the joint's clusters); sampled: -1
    std::int32_t rotation = 0; // sampled: index in rotations() of R(first); R(first .. last + 1) follow
    std::int32_t previous = -1; // the joint's latest cluster that ended at or before `first`, or -1
    // What the evaluator reads, ready-made: rotations at rotations()[base + step * i0] and the
    // next one; the constant local matrix locals()[local] (frozen segments; else the joint's
    // static local matrix, unused).
    std::int32_t base = 0;
    std::int32_t step = 0;
    std::int32_t local = 0;
  };
  struct Cluster {
    std::int32_t first = 0; // frames, inclusive
    std::int32_t last = 0;
    std::int32_t key = 0;
    std::int32_t keyPair = 0; // index in rotations() of two copies of the key's rotation
    glm::quat lastRotation{1.0f, 0.0f, 0.0f, 0.0f}; // q(last), the original rotation, sign-aligned with R(last + 1)
    glm::quat exitOffset{1.0f, 0.0f, 0.0f, 0.0f};   // D = key * q(last)^-1, w >= 0; identity at the clip's end
    std::int32_t local = 0; // locals()[local]: the key posture's local matrix (static translation and scale)
    std::int32_t joint = 0; // the joint it belongs to
  };
  // The plan of frame i0: what the evaluator reads there, the same for every character
  // playing the clip (docs/architecture.md section 5: precomputed per clip frame, nothing
  // rebuilt per character), in one contiguous record (floats, 64-byte aligned) so that a
  // character-frame reads a few consecutive cache lines:
  // - header, kPlanHeader floats: word 0 the sampled slots, word 1 their blocks of kLanes;
  // - refs, jointCount words (padded to kLanes): where each joint's local matrix is read,
  //   (source << kRefShift) | float offset: kRefPlan (a matrix in this plan, lane layout),
  //   kRefSlot (sampled slot k: the evaluator computes it at laneOffset(k) of its own
  //   buffer), kRefStatic (the joint's static local matrix in staticLocals());
  // - the sampled slots (rotation animated outside a cluster, in an unfreeze window, or
  //   translation or scale animated), in joint order, blocks of kLanes: planArrays() arrays
  //   of kLanes floats (PlanArray): the rotation at i0 and its step to i0 + 1 (lerped and
  //   normalised: nlerp), the translation at i0 and its step, and in a scaled clip the
  //   scale and its step; lanes past the last slot hold the identity;
  // - the constant local matrices of joints frozen in a cluster (the key posture), lane
  //   layout, blocks of kLanes.
  // Words are uint32 stored bit for bit in floats (planWord()).
  static constexpr int kPlanHeader = 8;
  static constexpr std::uint32_t kRefShift = 30;
  static constexpr std::uint32_t kRefPlan = 0, kRefSlot = 1, kRefStatic = 2;
  static constexpr std::uint32_t kRefOffset = (1u << kRefShift) - 1;
  // clang-format off
  enum PlanArray : int { kQx, kQy, kQz, kQw, kDx, kDy, kDz, kDw, kTx0, kTy0, kTz0, kTdx, kTdy, kTdz,
                         kSx0, kSy0, kSz0, kSdx, kSdy, kSdz, kPlanArraysScaled };
  // clang-format on
  static constexpr int kPlanArrays = kSx0; // an unscaled clip's
  static std::uint32_t planWord(float f) { return std::bit_cast<std::uint32_t>(f); }
  static float planFloat(std::uint32_t w) { return std::bit_cast<float>(w); }
  // Local matrices in lane layout: blocks of kLanes matrices, each block kLocalArrays arrays
  // of kLanes floats: the 3x3 rotation-scale part column by column (m00 m01 m02 m10 ... m22),
  // then the translation x y z. Element e of matrix i is at laneOffset(i) + kLanes * e.
  static constexpr int kLanes = 8;
  static constexpr int kLocalArrays = 12;
  static constexpr std::uint32_t laneOffset(std::uint32_t i) {
    return (i / kLanes) * (kLanes * kLocalArrays) + i % kLanes;
  }
  enum JointFlags : std::uint8_t {
    kRotationAnimated = 1,
    kTranslationAnimated = 2,
    kScaleAnimated = 4,
    kScaled = 8, // a scale other than 1 at some frame (animated, or static but not 1)
  };

  LodClip() = default;

  // Checks `source` and builds the clip; on bad input returns nothing and, where
  // out_error is given, says why.
  static std::optional<LodClip> build(const LodClipSource& source, std::string* out_error = nullptr);

  int jointCount() const { return m_jointCount; }
  int frameCount() const { return m_frameCount; }
  double fps() const { return m_fps; }
  bool looping() const { return m_looping; }
  // (frameCount - 1) / fps seconds: the last frame's time, and a looping clip's period.
  double duration() const { return m_frameCount > 1 ? (m_frameCount - 1) / m_fps : 0.0; }
  int clusterCount() const { return static_cast<int>(m_clusters.size()); }
  // Bytes the clip holds (what an engine pays per clip and level).
  std::size_t byteSize() const;
  // Joints with an animated channel (rotation, translation or scale): what full detail
  // samples every frame.
  int animatedJointCount() const;

  // Frame position (frames, in [0, frameCount - 1]) of `seconds`, and for a looping clip
  // the number of whole periods before it (0 otherwise). A non-looping clip clamps.
  double framePosition(double seconds, std::int64_t* out_loop = nullptr) const {
    const double g = seconds * m_fps;
    const double last = static_cast<double>(m_frameCount - 1);
    if (!m_looping || m_frameCount < 2) {
      if (out_loop)
        *out_loop = 0;
      return g < 0.0 ? 0.0 : (g > last ? last : g);
    }
    return wrapped(g, out_loop);
  }

  // Joint j at frame position f in [0, frameCount - 1]: the rotation of M'(f) with the
  // unfreeze blends of `blendFrames` (0 = none), its translation and scale. The reference
  // path (tools, tests, level changes); the evaluator gives the same values faster.
  glm::quat rotationAt(int joint, double frame, int blendFrames = 0) const;
  glm::vec3 translationAt(int joint, double frame) const;
  glm::vec3 scaleAt(int joint, double frame) const;

  // The layout the evaluator reads.
  std::uint8_t flags(int joint) const { return m_flags[static_cast<std::size_t>(joint)]; }
  // Static joints: their constant rotation (as a pair, for uniform sampling), translation,
  // scale and local matrix.
  std::int32_t staticRotationPair(int joint) const { return m_staticPair[static_cast<std::size_t>(joint)]; }
  const glm::vec3& staticTranslation(int joint) const { return m_staticTranslation[static_cast<std::size_t>(joint)]; }
  const glm::vec3& staticScale(int joint) const { return m_staticScale[static_cast<std::size_t>(joint)]; }
  const glm::mat4& staticLocal(int joint) const { return m_locals[static_cast<std::size_t>(joint)]; }
  // Constant local matrices: the static one of each joint (index = joint), then each cluster's key.
  std::span<const glm::mat4> locals() const { return m_locals; }
  // Animated translation / scale: the track's first element, frameCount values; null when static.
  const glm::vec3* translationTrack(int joint) const {
    const std::int32_t at = m_translationTrack[static_cast<std::size_t>(joint)];
    return at < 0 ? nullptr : &m_tracks[static_cast<std::size_t>(at)];
  }
  const glm::vec3* scaleTrack(int joint) const {
    const std::int32_t at = m_scaleTrack[static_cast<std::size_t>(joint)];
    return at < 0 ? nullptr : &m_tracks[static_cast<std::size_t>(at)];
  }
  std::span<const Segment> segments(int joint) const {
    const std::size_t j = static_cast<std::size_t>(joint);
    return {m_segments.data() + m_segmentBegin[j], m_segmentBegin[j + 1] - m_segmentBegin[j]};
  }
  std::span<const Cluster> clusters(int joint) const {
    const std::size_t j = static_cast<std::size_t>(joint);
    return {m_clusters.data() + m_clusterBegin[j], m_clusterBegin[j + 1] - m_clusterBegin[j]};
  }
  std::span<const glm::quat> rotations() const { return m_rotations; }
  // Every joint's static local matrix (index = joint) in lane layout (laneOffset()): what
  // kRefStatic refs point into.
  const float* staticLocals() const { return m_staticLocals.data(); }
  // A scale other than 1 somewhere in the clip (else the evaluator skips scales).
  bool scaled() const { return m_scaled; }
  // Frames of unfreeze blending the plans are made for (0 = none).
  int blendFrames() const { return m_blendFrames; }
  // Makes the plans for `frames` of unfreeze blending ([0, kMaxBlendFrames]). Not while a job reads
  // the clip. A clip without clusters has no windows: only the figure changes.
  void setBlendFrames(int frames);
  // Index of the segment of `joint` that holds frame i0 (binary search).
  int findSegment(int joint, int i0) const;
  // The plan of frame i0 in [0, planFrames()), planFrames() = max(frameCount - 1, 1).
  int planFrames() const { return static_cast<int>(m_planBegin.size()) - 1; }
  const float* plan(int i0) const { return m_plans.data() + m_planBegin[static_cast<std::size_t>(i0)]; }
  // Floats of the largest plan (a multiple of 16: whole cache lines).
  std::size_t maxPlanFloats() const { return m_maxPlanFloats; }
  // Arrays of a sampled slot block (kPlanArrays, or kPlanArraysScaled in a scaled clip) and
  // where the first block starts in a plan (after header and refs), in floats.
  int planArrays() const { return m_scaled ? kPlanArraysScaled : kPlanArrays; }
  int planSlotsAt() const { return kPlanHeader + (m_jointCount + kLanes - 1) / kLanes * kLanes; }
  // Bytes of the plans (included in byteSize()).
  std::size_t planByteSize() const;
  // Does frame i0 of `joint` lie in an unfreeze window of `blendFrames` frames (after one
  // of its clusters that ends before the clip does)?
  bool inUnfreezeWindow(int joint, int i0, int blendFrames) const;
  std::span<const Cluster> allClusters() const { return m_clusters; }
  // i0 (the frame at or before the frame position, at most frameCount - 2) and the
  // fraction past it.
  void split(double frame, std::int32_t& out_i0, float& out_fraction) const {
    const std::int32_t lastI0 = m_frameCount > 2 ? m_frameCount - 2 : 0;
    std::int32_t i0 = frame > 0.0 ? static_cast<std::int32_t>(frame) : 0; // frame >= 0: truncation is floor
    i0 = i0 < lastI0 ? i0 : lastI0;
    const float fraction = static_cast<float>(frame - i0);
    out_i0 = i0;
    out_fraction = fraction < 0.0f ? 0.0f : (fraction > 1.0f ? 1.0f : fraction);
  }

private:
  // The per-frame plans and static locals in lane layout of a clip whose tracks, segments
  // and clusters are built.
  void buildPlans();
  // The rotation with unfreeze blends composed at frame position `frame` (V(k) of the
  // header at whole frames).
  glm::quat composedRotation(int joint, double frame, int blendFrames) const;
  // Linear interpolation of a per-frame track at a fractional frame.
  glm::vec3 interpolate(const glm::vec3* track, double frame) const;
  double wrapped(double g, std::int64_t* out_loop) const;

  double m_fps = 30.0;
  std::int32_t m_frameCount = 0;
  std::int32_t m_jointCount = 0;
  bool m_looping = false;
  std::vector<std::uint8_t> m_flags;
  std::vector<std::int32_t> m_staticPair;
  std::vector<glm::vec3> m_staticTranslation;
  std::vector<glm::vec3> m_staticScale;
  std::vector<glm::mat4> m_locals; // joints' static local matrices, then clusters' key local matrices
  std::vector<std::int32_t> m_translationTrack; // per joint: start in m_tracks, or -1
  std::vector<std::int32_t> m_scaleTrack;
  std::vector<glm::vec3> m_tracks;
  std::vector<std::uint32_t> m_segmentBegin; // jointCount + 1
  std::vector<Segment> m_segments;
  std::vector<std::uint32_t> m_clusterBegin; // jointCount + 1
  std::vector<Cluster> m_clusters;
  std::vector<glm::quat> m_rotations;
  bool m_scaled = false;
  int m_blendFrames = 0;
  std::vector<float> m_staticLocals;
  std::vector<std::uint32_t> m_planBegin; // planFrames() + 1 offsets in m_plans, floats
  std::vector<float, CacheLineAllocator<float>> m_plans;
  std::size_t m_maxPlanFloats = 0;
};

// The same rotation with w >= 0.
inline glm::quat positiveW(const glm::quat& q) { return q.w < 0.0f ? -q : q; }

// nlerp(identity, offset, weight): the offset scaled down to `weight` in [0, 1] (offset.w >= 0).
inline glm::quat scaleOffset(const glm::quat& offset, float weight) {
  const glm::quat q(1.0f - weight + weight * offset.w, weight * offset.x, weight * offset.y, weight * offset.z);
  return q * (1.0f / std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w));
}

} // namespace mlod
