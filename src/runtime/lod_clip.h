#pragma once
// A clip as the runtime plays it at one LOD level (docs/architecture.md section 5; Ahn & Wohn,
// "Motion Level-of-Detail", section 4), compressed: per joint, its clusters (runs of frames
// frozen at one key posture: one stored key each), the rotations of the frames outside
// clusters, and the translation and scale tracks of the joints that animate them (the
// root's translation above all), every value quantized (internal/compressed_tracks.h) so
// that no joint, and no point 3 cm from one, moves by more than the precision (default
// 0.01 cm) against the unquantized clip. The precision is shared out: each animated channel
// on the longest chain from a root gets an equal part, and a rotation's part is divided by
// its lever (the longest chain of bones below it, scaled, plus the 3 cm shell). A clip
// built without clusters is "full detail": the same data, the same evaluator.
//
// Time: frames are uniform, frame i plays at i / fps seconds. Between frames, rotations are
// normalised-lerped (the shorter way) and translations and scales lerped. A "frame
// position" is time x fps, in frames. Lengths are in cm. Immutable once built; any number
// of characters share one.
//
// What a cluster changes: a joint j with cluster [first, last] holds the key frame's
// rotation at every frame of the cluster, so at frame positions f in [first, last] its
// rotation is constant; this is M'(t) of the paper. Translations and scales are never
// clustered, so a joint is *frozen* (its whole local matrix constant) only inside a
// cluster and when its translation and scale tracks are constant.
//
// Unfreeze blending (docs/architecture.md section 5): when a cluster [first, last] of a joint ends
// before the clip does, its rotation jumps within one frame from the key to the next
// frame's. A clip built with blendFrames = N > 0 spreads the jump over N frames: at every
// frame i in the window (last, last + N) the joint shows
//     nlerp(identity, D, 1 - (i - last) / N) * M'(i),    D = key * q(last)^-1,
// the cluster's own error at its last frame decaying to nothing (windows of consecutive
// clusters that overlap compose, older offsets outermost), and between frames the nlerp of
// two frames, as everywhere. So the clip stores the blended frames themselves: the frames
// of a window are entries like any frame outside a cluster, and a cluster freezes only the
// frames no earlier window reaches (a cluster left with fewer than 2 such frames freezes
// none). The blend equals the key at frame last and M' from last + N on, and differs from
// M' inside by the angle of D at most, an error M' already makes inside the cluster (the
// joint stays within the level's joint-position fidelity). N is part of the clip: the
// evaluator plays it with that N (PoseEvaluatorJob::blendFrames) and decodes no window
// of its own.
//
// Held or sampled (the cheaper of cluster look-up and sampling, per cluster): holding a
// frozen joint costs the evaluator about nothing per evaluation, but each cluster costs
// look-ups where it begins and ends (its region, its key). A cluster's frozen frames are
// kept frozen only where the runtime holds them for at least kMinHeldEvaluations
// evaluations (frames x LodClipSource::evaluationsPerSecond / fps; default a 60 Hz
// display); otherwise they are stored and sampled like any other frame. The joint shows
// the same rotation either way (the key's, within the precision). Callgrind per
// character-frame, CMU 01_01 at E = 5 / 50 / 300 and Boxing_Toes (100 fps) at E = 50,
// held always -> with 5 evaluations: 6,425 -> 6,244, 5,790 -> 5,715, 4,941 -> 4,922,
// 5,039 -> 4,911 (full detail 6,378 and 4,910).

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "runtime/internal/compressed_tracks.h"

#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace mlod {

namespace internal {
struct LodClipStorage; // a clip's storage in a runtime bundle (bundle.cpp)
}

// The most frames of unfreeze and level-change blending (LodClipSource::blendFrames,
// PoseEvaluatorJob::blendFrames, Crowd and the CLI's --blend-frames).
inline constexpr int kMaxBlendFrames = 10000;
// The fewest evaluations a cluster's frozen frames must be held for to be stored frozen
// (the header's "Held or sampled"): chosen from callgrind runs at 0, 1, 1.5, 2, 3, 5, 8,
// 12 on CMU 01_01, 01_03 and Boxing_Toes.
inline constexpr double kMinHeldEvaluations = 5.0;
// The default precision of a clip's quantization (cm; LodClipSource::precisionCm).
inline constexpr double kDefaultClipPrecisionCm = 0.01;

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
  // Frames of unfreeze blending the clip is built for and played with, [0,
  // kMaxBlendFrames] (0 = none: M'(t); the header's "Unfreeze blending").
  int blendFrames = 0;
  // How often the runtime evaluates the clip (Hz): a cluster is held only where that saves
  // more than its look-ups cost (the header's "Held or sampled"), in (0, 1e6].
  double evaluationsPerSecond = 60.0;
  // The skeleton (parent of each joint, parents first, -1 for a root), or none: it shares
  // the precision out along chains (LodClip's header); without it the bounds are coarser
  // and the clip larger.
  std::span<const std::int16_t> parents;
  // The largest error quantization may add to any joint, and to any point 3 cm from one
  // (cm; ACL's default precision and shell), in (0, 1000].
  double precisionCm = kDefaultClipPrecisionCm;
};

class LodClip {
public:
  // The frozen frames of one cluster of a joint as the clip holds them (a view: clusters()
  // decodes it): with blending, those no earlier window reaches.
  struct Cluster {
    std::int32_t first = 0; // frames, inclusive
    std::int32_t last = 0;
    glm::quat key{1.0f, 0.0f, 0.0f, 0.0f}; // the key posture's rotation, as decoded
    std::int32_t joint = 0;
  };
  // A region of a joint's rotation (the storage the evaluator walks): a cluster [first,
  // last] frozen at its key, then the frames up to the next region's first, each stored. A
  // joint's first region starts at frame 0; where no cluster does, it is frame 0 alone (a
  // one-frame "cluster" that freezes nothing). Its entries in the joint's rotation stream:
  // the key at `entry`, frame i > last at entry + i - last. Each joint's regions end with a
  // sentinel {frameCount, the stream's entry count}, so that last = next.first - next.entry
  // + entry. Stored in 16 bits each where the clip has at most 65,535 frames, else 32.
  struct Region {
    std::int32_t first = 0;
    std::uint32_t entry = 0;
  };
  // A joint's regions as stored (regionWords()): one word a region, first frame in the low
  // 16 bits and first entry in the high (narrow), or two words, first and entry (wide).
  struct NarrowRegions {
    const std::uint32_t* words;
    std::int32_t first(std::uint32_t r) const { return static_cast<std::int32_t>(words[r] & 0xffffu); }
    std::uint32_t entry(std::uint32_t r) const { return words[r] >> 16; }
  };
  struct WideRegions {
    const std::uint32_t* words;
    std::int32_t first(std::uint32_t r) const { return static_cast<std::int32_t>(words[2 * static_cast<std::size_t>(r)]); }
    std::uint32_t entry(std::uint32_t r) const { return words[2 * static_cast<std::size_t>(r) + 1]; }
  };
  enum JointFlags : std::uint8_t {
    kRotationAnimated = 1,
    kTranslationAnimated = 2,
    kScaleAnimated = 4,
    kScaled = 8, // a scale other than 1 at some frame (animated, or static but not 1)
    kEveryFrame = 16, // its rotation animates and has no cluster: entry i is frame i (one region)
  };
  static constexpr std::uint8_t kAnimated = kRotationAnimated | kTranslationAnimated | kScaleAnimated;
  // Local matrices in lane layout (the evaluator's): blocks of kLanes matrices, each block
  // kLocalArrays arrays of kLanes floats: the 3x3 rotation-scale part column by column (m00
  // m01 m02 m10 ... m22), then the translation x y z. Element e of matrix i is at
  // laneOffset(i) + kLanes * e.
  static constexpr int kLanes = 8;
  static constexpr int kLocalArrays = 12;
  static constexpr std::uint32_t laneOffset(std::uint32_t i) {
    return (i / kLanes) * (kLanes * kLocalArrays) + i % kLanes;
  }

  LodClip() = default;

  // Checks `source` and builds the clip; on bad input returns nothing and, where
  // out_error is given, says why.
  static std::optional<LodClip> build(const LodClipSource& source, std::string* out_error = nullptr);
  // Why the clip's storage breaks a rule that the evaluator and the reference path rely on
  // to read within bounds (empty when it keeps them all): regions sorted, each joint's from
  // frame 0 to its sentinel, entries in range; streams, chunks and bits that hold what the
  // regions and frames address; flags that match the streams; finite values. build() keeps
  // them; a clip read from a file (a runtime bundle) is checked with this before it is used.
  std::string storageProblem() const;

  int jointCount() const { return m_jointCount; }
  int frameCount() const { return m_frameCount; }
  double fps() const { return m_fps; }
  bool looping() const { return m_looping; }
  // (frameCount - 1) / fps seconds: the last frame's time, and a looping clip's period.
  double duration() const { return m_frameCount > 1 ? (m_frameCount - 1) / m_fps : 0.0; }
  int clusterCount() const { return m_clusterCount; }
  // Bytes the clip holds: everything the evaluator reads (what an engine pays per clip and level).
  std::size_t byteSize() const;
  // Joints with an animated channel (rotation, translation or scale): what full detail
  // samples every frame.
  int animatedJointCount() const;
  // The precision the clip was encoded to (cm: joint and 3 cm shell positions, LodClipSource),
  // and the largest error the encoder measured, bounded the same way (cm; <= precision).
  double precisionCm() const { return m_precisionCm; }
  // byteSize() per second of animation (0 for a one-frame clip).
  double bytesPerSecond() const;
  double encodedErrorCm() const { return m_encodedErrorCm; }

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
  // clip's unfreeze blends (blendFrames()), its translation and scale, as decoded. The
  // reference path (tools, tests, level changes); the evaluator gives the same values
  // faster.
  glm::quat rotationAt(int joint, double frame) const;
  glm::vec3 translationAt(int joint, double frame) const;
  glm::vec3 scaleAt(int joint, double frame) const;
  // The clusters of a joint as stored (their frozen frames and key), decoded.
  std::vector<Cluster> clusters(int joint) const;

  std::uint8_t flags(int joint) const { return m_flags[static_cast<std::size_t>(joint)]; }
  const std::uint8_t* jointFlags() const { return m_flags.data(); }
  // Static channels: the constant value (for an animated channel, its first frame's).
  const glm::quat& staticRotation(int joint) const { return m_staticRotation[static_cast<std::size_t>(joint)]; }
  const glm::vec3& staticTranslation(int joint) const { return m_staticTranslation[static_cast<std::size_t>(joint)]; }
  const glm::vec3& staticScale(int joint) const { return m_staticScale[static_cast<std::size_t>(joint)]; }
  // A scale other than 1 somewhere in the clip (else the evaluator skips scales).
  bool scaled() const { return m_scaled; }
  // Frames of unfreeze blending the clip was built for (LodClipSource::blendFrames; 0 =
  // none): the N it must be played with (PoseEvaluatorJob checks it).
  int blendFrames() const { return m_blendFrames; }
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
  // Is joint j frozen between frames i0 and i0 + 1 (both among one cluster's frozen
  // frames, translation and scale static)?
  bool frozen(int joint, int i0) const;

  // The storage the evaluator reads (docs/architecture.md section 5, "Compressed clips").
  // Joints whose rotation animates, and joints whose translation or scale does, in order.
  std::span<const std::int16_t> rotationJoints() const { return m_rotationJoints; }
  std::span<const std::int16_t> vectorJoints() const { return m_vectorJoints; }
  // A joint's stream of rotations (entries by Region), translations and scales (one entry
  // per frame); -1 when the channel is static. The rotation streams come first, in joint
  // order: the i-th joint of rotationJoints() reads stream i.
  int rotationStream(int joint) const { return m_rotationStream[static_cast<std::size_t>(joint)]; }
  int translationStream(int joint) const { return m_translationStream[static_cast<std::size_t>(joint)]; }
  int scaleStream(int joint) const { return m_scaleStream[static_cast<std::size_t>(joint)]; }
  const internal::CompressedStreams& streams() const { return m_streams; }
  // Regions of joint j: region(regionBegin(j)) .. region(regionBegin(j + 1) - 2), then
  // its sentinel, stored as NarrowRegions or WideRegions say (narrowRegions()).
  std::uint32_t regionCount() const {
    return static_cast<std::uint32_t>(m_narrowRegions ? m_regionWords.size() : m_regionWords.size() / 2);
  }
  std::int32_t regionFirst(std::uint32_t r) const {
    return m_narrowRegions ? NarrowRegions{m_regionWords.data()}.first(r) : WideRegions{m_regionWords.data()}.first(r);
  }
  std::uint32_t regionEntry(std::uint32_t r) const {
    return m_narrowRegions ? NarrowRegions{m_regionWords.data()}.entry(r) : WideRegions{m_regionWords.data()}.entry(r);
  }
  Region region(std::uint32_t r) const { return Region{regionFirst(r), regionEntry(r)}; }
  bool narrowRegions() const { return m_narrowRegions; }
  const std::uint32_t* regionWords() const { return m_regionWords.data(); }
  std::uint32_t regionBegin(int joint) const { return m_regionBegin[static_cast<std::size_t>(joint)]; }
  // The region of joint j (rotation animated) that holds frame i (absolute index).
  std::uint32_t regionOf(int joint, std::int32_t i) const;
  // The last frame of region r's cluster.
  std::int32_t lastOf(std::uint32_t r) const {
    return regionFirst(r + 1) - static_cast<std::int32_t>(regionEntry(r + 1)) + static_cast<std::int32_t>(regionEntry(r));
  }
  // The rotation stream's entry of frame i in region r (i up to the next region's first).
  std::uint32_t entryOf(std::uint32_t r, std::int32_t i) const {
    const std::int32_t last = lastOf(r);
    return regionEntry(r) + static_cast<std::uint32_t>(i > last ? i - last : 0);
  }
  glm::quat rotationEntry(int joint, std::uint32_t entry) const {
    return internal::toQuat(m_streams.value(rotationStream(joint), entry));
  }

private:
  friend struct internal::LodClipStorage;
  // The joint lists and flags that follow from the per-joint flags (build() and a reader).
  void deriveJointLists();
  glm::vec3 vectorAt(int stream, const glm::vec3& fixed, double frame) const;
  double wrapped(double g, std::int64_t* out_loop) const;

  double m_fps = 30.0;
  std::int32_t m_frameCount = 0;
  std::int32_t m_jointCount = 0;
  bool m_looping = false;
  bool m_scaled = false;
  int m_blendFrames = 0;
  int m_clusterCount = 0;
  double m_precisionCm = 0.0;
  double m_encodedErrorCm = 0.0;
  std::vector<std::uint8_t> m_flags;
  std::vector<glm::quat> m_staticRotation;
  std::vector<glm::vec3> m_staticTranslation;
  std::vector<glm::vec3> m_staticScale;
  std::vector<std::int16_t> m_rotationJoints;
  std::vector<std::int16_t> m_vectorJoints;
  std::vector<std::int32_t> m_rotationStream;
  std::vector<std::int32_t> m_translationStream;
  std::vector<std::int32_t> m_scaleStream;
  std::vector<std::uint32_t> m_regionBegin; // jointCount + 1 (a joint's sentinel is at the next one's begin - 1)
  std::vector<std::uint32_t> m_regionWords;
  bool m_narrowRegions = true;
  internal::CompressedStreams m_streams;
};

// The same rotation with w >= 0.
// Bytes over a duration in seconds (0 for a one-frame clip): bytes per second of animation.
inline double bytesPerSecond(std::size_t bytes, double seconds) {
  return seconds > 0.0 ? static_cast<double>(bytes) / seconds : 0.0;
}

inline glm::quat positiveW(const glm::quat& q) { return q.w < 0.0f ? -q : q; }

// nlerp(identity, offset, weight): the offset scaled down to `weight` in [0, 1] (offset.w >= 0).
inline glm::quat scaleOffset(const glm::quat& offset, float weight) {
  const glm::quat q(1.0f - weight + weight * offset.w, weight * offset.x, weight * offset.y, weight * offset.z);
  return q * (1.0f / std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w));
}

} // namespace mlod
