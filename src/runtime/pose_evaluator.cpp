// The crowd pose evaluator: per character a *plan* (which joints are active, where their
// rotations are read, the folded matrices of frozen chains) that holds for a range of
// frames, rebuilt incrementally when a joint's cluster starts or ends; per frame, the
// active joints are sampled structure-of-arrays and the hierarchy is walked once.
#include "runtime/pose_evaluator.h"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstring>

// The hot path is also compiled for x86-64-v3 (AVX2, FMA) and picked at load time.
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__)) && !defined(MLOD_NO_TARGET_CLONES)
#define MLOD_RUNTIME_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define MLOD_RUNTIME_CLONES
#endif

namespace mlod {

namespace {

// The active joints' sampling buffers, in blocks of 8 joints (array-of-structures-of-arrays):
// value `array` of active slot k is at [(k / 8) * kBlockFloats + array * 8 + k % 8], so that
// a block computes 8 joints at once and the hierarchy reads a joint's values at constant
// offsets from one pointer.
enum SoaArray {
  kAx, kAy, kAz, kAw, // rotation at the frame before
  kBx, kBy, kBz, kBw, // rotation at the frame after
  kQx, kQy, kQz, kQw, // the interpolated rotation
  kM00, kM01, kM02, kM10, kM11, kM12, kM20, kM21, kM22, // local rotation x scale, columns
  kSx, kSy, kSz,       // local scale
  kSoaArrays
};
constexpr int kLanes = 8;
constexpr std::size_t kBlockFloats = kSoaArrays * kLanes;

// Joint status in a plan: bit 0 = active (its local matrix is computed this frame);
// constant joints (frozen or static) take a precomputed local matrix.
constexpr std::uint8_t kActive = 1;
constexpr std::uint8_t kBlend = 2; // its rotation gets blend offsets (implies active)
constexpr std::uint8_t kLevel = 8; // a level-change offset applies
constexpr std::uint8_t kWrap = 16; // a loop-wrap offset applies

constexpr std::uint8_t kAnimatedTranslationOrScale = LodClip::kTranslationAnimated | LodClip::kScaleAnimated;

// 4 floats in a vector register (GCC and clang vector extensions: SSE on x86-64, AVX/FMA in
// the x86-64-v3 clone).
typedef float v4 __attribute__((vector_size(16)));

inline v4 load4(const float* p) {
  v4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
inline void store4(float* p, v4 v) { std::memcpy(p, &v, sizeof v); }

// out = a x b for affine 4x4 matrices (column-major, bottom row 0 0 0 1; b's is not read).
// out must not alias a or b.
inline void mulAffine(const float* __restrict a, const float* __restrict b, float* __restrict out) {
  const v4 a0 = load4(a), a1 = load4(a + 4), a2 = load4(a + 8), a3 = load4(a + 12);
  store4(out, a0 * b[0] + a1 * b[1] + a2 * b[2]);
  store4(out + 4, a0 * b[4] + a1 * b[5] + a2 * b[6]);
  store4(out + 8, a0 * b[8] + a1 * b[9] + a2 * b[10]);
  store4(out + 12, a0 * b[12] + a1 * b[13] + a2 * b[14] + a3);
}

// Lerp of a block's 8 rotation pairs (stored rotations are sign-aligned: no sign test). Not
// normalised: matrixBlock() divides by the squared length, so that blend offsets can be
// composed as plain products.
inline void lerpBlock(float* __restrict b, float fraction) {
  for (int l = 0; l < kLanes; ++l) {
    b[kQx * kLanes + l] = b[kAx * kLanes + l] + (b[kBx * kLanes + l] - b[kAx * kLanes + l]) * fraction;
    b[kQy * kLanes + l] = b[kAy * kLanes + l] + (b[kBy * kLanes + l] - b[kAy * kLanes + l]) * fraction;
    b[kQz * kLanes + l] = b[kAz * kLanes + l] + (b[kBz * kLanes + l] - b[kAz * kLanes + l]) * fraction;
    b[kQw * kLanes + l] = b[kAw * kLanes + l] + (b[kBw * kLanes + l] - b[kAw * kLanes + l]) * fraction;
  }
}

// Rotation matrices of a block's 8 quaternions, of any non-zero length (glm::mat3_cast of
// the normalised quaternion: 2 becomes 2 / |q|^2), columns scaled.
inline void matrixBlock(float* __restrict b) {
  for (int l = 0; l < kLanes; ++l) {
    const float x = b[kQx * kLanes + l], y = b[kQy * kLanes + l], z = b[kQz * kLanes + l], w = b[kQw * kLanes + l];
    const float two = 2.0f / (x * x + y * y + z * z + w * w);
    const float xx = x * x * two, yy = y * y * two, zz = z * z * two, xy = x * y * two, xz = x * z * two,
                yz = y * z * two, wx = w * x * two, wy = w * y * two, wz = w * z * two;
    const float sx = b[kSx * kLanes + l], sy = b[kSy * kLanes + l], sz = b[kSz * kLanes + l];
    b[kM00 * kLanes + l] = (1.0f - (yy + zz)) * sx;
    b[kM01 * kLanes + l] = (xy + wz) * sx;
    b[kM02 * kLanes + l] = (xz - wy) * sx;
    b[kM10 * kLanes + l] = (xy - wz) * sy;
    b[kM11 * kLanes + l] = (1.0f - (xx + zz)) * sy;
    b[kM12 * kLanes + l] = (yz + wx) * sy;
    b[kM20 * kLanes + l] = (xz + wy) * sz;
    b[kM21 * kLanes + l] = (yz - wx) * sz;
    b[kM22 * kLanes + l] = (1.0f - (xx + yy)) * sz;
  }
}

// nlerp(identity, offset, weight) before normalisation: (1 - weight) identity + weight offset.
inline glm::quat lerpOffset(const glm::quat& offset, float weight) {
  return glm::quat(1.0f - weight + weight * offset.w, weight * offset.x, weight * offset.y, weight * offset.z);
}

glm::quat positiveW(const glm::quat& q) { return q.w < 0.0f ? -q : q; }

// An offset below float resolution changes nothing: the joint need not blend.
bool isIdentity(const glm::quat& q) { return std::abs(q.x) + std::abs(q.y) + std::abs(q.z) <= 1e-7f; }

// The rotation of `joint` that `clip` shows at `seconds` without level blending: M'
// with its unfreeze blends and, in a wrap window, the wrap offset.
glm::quat shownRotation(const LodClip& clip, int joint, double seconds, int blendFrames) {
  std::int64_t loop = 0;
  const double f = clip.framePosition(seconds, &loop);
  glm::quat q = clip.rotationAt(joint, f, blendFrames);
  std::int32_t i0 = 0;
  float fraction = 0.0f;
  clip.split(f, i0, fraction);
  if (blendFrames > 0 && clip.looping() && loop >= 1 && i0 < blendFrames) {
    const glm::quat wrap = positiveW(clip.rotationAt(joint, clip.frameCount() - 1, blendFrames) *
                                     glm::inverse(clip.rotationAt(joint, 0.0, blendFrames)));
    q = scaleOffset(wrap, static_cast<float>(1.0 - std::min(f / blendFrames, 1.0))) * q;
  }
  return q;
}

// Sets or clears bit j of a joint set.
inline void assign(std::uint64_t* set, int j, bool value) {
  const std::uint64_t bit = std::uint64_t{1} << (j & 63);
  set[j >> 6] = value ? set[j >> 6] | bit : set[j >> 6] & ~bit;
}
// Calls visit(j) for every joint of the set, in order.
template <typename Visit>
inline void forEachJoint(const std::uint64_t* set, std::size_t words, Visit&& visit) {
  for (std::size_t w = 0; w < words; ++w)
    for (std::uint64_t bits = set[w]; bits; bits &= bits - 1)
      visit(static_cast<int>(w * 64 + static_cast<std::size_t>(__builtin_ctzll(bits))));
}
} // namespace

struct PoseEvaluation {
  using State = PoseEvaluatorContext::CharacterState;
  using Scratch = PoseEvaluatorContext::Scratch;

  // Frames a character may step forward and still re-read only the joints whose events lie
  // in between; a longer jump (or any step back) re-reads every joint.
  static constexpr std::int32_t kIncrementalFrames = 64;

  static void runRange(void* data, int begin, int end, int thread) {
    const PoseEvaluatorJob& job = *static_cast<const PoseEvaluatorJob*>(data);
    Scratch& scratch = job.context->m_scratch[static_cast<std::size_t>(thread)];
    for (int c = begin; c < end; ++c)
      evaluate(job, c, scratch);
  }

  static void evaluate(const PoseEvaluatorJob& job, int c, Scratch& scratch) {
    PoseEvaluatorContext& ctx = *job.context;
    const LodClip& clip = *job.clips[static_cast<std::size_t>(c)];
    State& st = ctx.m_states[static_cast<std::size_t>(c)];
    const double t = job.times[static_cast<std::size_t>(c)];
    std::int64_t loop = 0;
    const double f = clip.framePosition(t, &loop);
    std::int32_t i0 = 0;
    float fraction = 0.0f;
    clip.split(f, i0, fraction);
    const int blendFrames = job.blendFrames;
    const bool models = !job.out_models.empty();

    bool full = !st.planValid || st.folding != job.folding || st.models != models || st.blendFrames != blendFrames;
    if (st.clip != &clip) {
      if (st.clip && st.planValid && blendFrames > 0 && st.blendFrames == blendFrames)
        startLevelBlend(job, c, t);
      else
        st.levelBlend = false;
      st.clip = &clip;
      std::fill_n(ctx.m_cursor.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(c) * ctx.m_joints),
                  ctx.m_joints, -1);
      full = true;
    }
    float levelWeight = 0.0f;
    if (st.levelBlend) {
      const double w = (t - st.levelStart) / st.levelSeconds;
      if (w >= 0.0 && w < 1.0) {
        levelWeight = static_cast<float>(1.0 - w);
      } else {
        st.levelBlend = false;
        full = true;
      }
    }
    const bool wrapWindow = blendFrames > 0 && clip.looping() && loop >= 1 && i0 < blendFrames;
    if (wrapWindow != st.wrapWindow || (wrapWindow && loop != st.loop))
      full = true;
    st.loop = loop;
    st.wrapWindow = wrapWindow;
    full = full || i0 < st.i0 || i0 - st.i0 > kIncrementalFrames;
    if (full || i0 != st.i0)
      scratch.rebuilds += rebuild(job, c, i0, full, scratch) ? 1 : 0;
    pose(job, c, f, i0, fraction, levelWeight, scratch);
    scratch.sampled += st.activeCount;
  }

  // The rotations shown before the switch, against the new clip's at the same time.
  static void startLevelBlend(const PoseEvaluatorJob& job, int c, double t) {
    PoseEvaluatorContext& ctx = *job.context;
    State& st = ctx.m_states[static_cast<std::size_t>(c)];
    const LodClip& before = *st.clip;
    const LodClip& after = *job.clips[static_cast<std::size_t>(c)];
    const int blendFrames = job.blendFrames;
    double previousWeight = -1.0;
    if (st.levelBlend) {
      const double w = (t - st.levelStart) / st.levelSeconds;
      if (w >= 0.0 && w < 1.0)
        previousWeight = 1.0 - w;
    }
    const std::size_t base = static_cast<std::size_t>(c) * static_cast<std::size_t>(ctx.m_joints);
    for (int j = 0; j < ctx.m_joints; ++j) {
      glm::quat shown = shownRotation(before, j, t, blendFrames);
      glm::quat& offset = ctx.m_levelOffset[base + static_cast<std::size_t>(j)];
      if (previousWeight >= 0.0)
        shown = scaleOffset(offset, static_cast<float>(previousWeight)) * shown;
      offset = positiveW(shown * glm::inverse(shownRotation(after, j, t, blendFrames)));
    }
    st.levelBlend = true;
    st.levelStart = t;
    st.levelSeconds = blendFrames / after.fps();
  }

  // Re-reads joint j of character c at frame i0: its segment, unfreeze windows and blend
  // offsets. Returns true when the joint toggled between active and constant, or now holds
  // another constant local matrix. Written without branches on the joint's state where it
  // can be: which joints have events differs from character to character, and a
  // mispredicted branch costs as much as a matrix product.
  static bool updateJoint(const PoseEvaluatorJob& job, const State& st, std::size_t i, int j, std::int32_t i0,
                          bool full) {
    PoseEvaluatorContext& ctx = *job.context;
    const LodClip& clip = *st.clip;
    const int blendFrames = job.blendFrames;
    const std::uint8_t oldStatus = ctx.m_status[i];
    const glm::mat4* oldLocal = ctx.m_constLocal[i];
    const std::uint8_t flags = clip.flags(j);
    std::int32_t rotationIndex = clip.staticRotationPair(j), rotationStep = 0, windowLatest = -1, windowCount = 0;
    const glm::mat4* local = &clip.staticLocal(j);
    bool frozen = true;
    if (flags & LodClip::kRotationAnimated) {
      const LodClip::Segment* segments = clip.segments(j).data();
      int s = ctx.m_cursor[i];
      if (s < 0) {
        s = clip.findSegment(j, i0);
      } else {
        // usually the next segment; far jumps search
        int steps = 0;
        while (i0 > segments[s].last && ++steps < 4)
          ++s;
        if (i0 < segments[s].first || i0 > segments[s].last)
          s = clip.findSegment(j, i0);
      }
      ctx.m_cursor[i] = s;
      const LodClip::Segment& segment = segments[s];
      rotationIndex = segment.base;
      rotationStep = segment.step;
      local = &clip.locals()[static_cast<std::size_t>(segment.local)];
      frozen = segment.cluster >= 0;
      if (blendFrames > 0) {
        const LodClip::Cluster* clusters = clip.clusters(j).data();
        for (int cc = segment.previous; cc >= 0 && clusters[cc].last + blendFrames > i0; --cc)
          ++windowCount;
        windowLatest = segment.previous;
      }
    }
    const bool level = st.levelBlend && !isIdentity(ctx.m_levelOffset[i]);
    const bool wrap = st.wrapWindow && !isIdentity(ctx.m_wrapOffset[i]);
    const bool blend = (windowCount > 0) | level | wrap;
    const bool constant = frozen & !(flags & kAnimatedTranslationOrScale) & !blend;
    const std::uint8_t status = static_cast<std::uint8_t>((constant ? 0 : kActive) | (blend ? kBlend : 0) |
                                                          (level ? kLevel : 0) | (wrap ? kWrap : 0));
    ctx.m_status[i] = status;
    ctx.m_constLocal[i] = constant ? local : nullptr;
    if (constant && (oldLocal != local || full)) // (full: the clip may be new at an old address)
      ctx.m_local[i] = *local; // the character's own copy: read every frame, next to its other state
    ctx.m_rotationIndex[i] = rotationIndex;
    ctx.m_rotationStep[i] = rotationStep;
    ctx.m_windowLatest[i] = windowLatest;
    ctx.m_windowCount[i] = windowCount;
    return ((oldStatus ^ status) & kActive) | (constant & (oldLocal != local));
  }

  // Makes the plan of character c hold at frame i0. `full`: re-reads every joint. Else the
  // character steps forward from the frame of its plan, and only the joints with an event
  // in between are re-read: a segment that starts (a cluster starts or ends) or an unfreeze
  // window that ends, straight from the clip's per-frame lists. Then refolds the frozen joints below the ones that changed
  // (palette-only jobs). Returns false when no joint had an event.
  static bool rebuild(const PoseEvaluatorJob& job, int c, std::int32_t i0, bool full, Scratch& scratch) {
    PoseEvaluatorContext& ctx = *job.context;
    State& st = ctx.m_states[static_cast<std::size_t>(c)];
    const LodClip& clip = *st.clip;
    const int joints = ctx.m_joints;
    const std::size_t words = ctx.m_words;
    const std::size_t base = static_cast<std::size_t>(c) * static_cast<std::size_t>(joints);
    std::uint64_t* activeSet = &ctx.m_activeSet[static_cast<std::size_t>(c) * words];
    std::uint8_t* __restrict changed = scratch.changed.data();
    std::uint8_t* __restrict foldChanged = scratch.foldChanged.data();
    const std::uint8_t* statuses = &ctx.m_status[base];
    const std::int16_t* parents = job.parents.data();
    const int blendFrames = job.blendFrames;
    // only palette-only jobs fold: a frozen joint whose model matrix is written costs one
    // product from its parent's, folded or not
    const bool folds = job.folding && job.out_models.empty();

    bool any = false, statusChanged = full;
    int firstChanged = joints;
    std::int32_t active = st.activeCount;
    const auto reread = [&](int j) {
      const std::uint8_t before = statuses[j];
      const bool toggled = updateJoint(job, st, base + static_cast<std::size_t>(j), j, i0, full) || full;
      const std::uint8_t status = statuses[j];
      changed[j] = changed[j] | toggled;
      firstChanged = toggled ? std::min(firstChanged, j) : firstChanged;
      statusChanged = statusChanged | (status != before);
      active += (status & kActive) - (full ? 0 : (before & kActive));
      assign(activeSet, j, status & kActive);
      any = true;
    };
    if (full) {
      if (st.wrapWindow)
        for (int j = 0; j < joints; ++j)
          ctx.m_wrapOffset[base + static_cast<std::size_t>(j)] =
              positiveW(clip.rotationAt(j, clip.frameCount() - 1, blendFrames) *
                        glm::inverse(clip.rotationAt(j, 0.0, blendFrames)));
      active = 0;
      for (int j = 0; j < joints; ++j)
        reread(j);
    } else {
      // a joint on two lists is re-read twice: harmless, it reads the same state
      for (std::int32_t x = st.i0 + 1; x <= i0; ++x) {
        for (std::int16_t j : clip.segmentStarts(x))
          reread(j);
        if (blendFrames > 0 && x - blendFrames >= 0)
          for (std::int16_t j : clip.clusterEnds(x - blendFrames)) // the unfreeze window ends
            reread(j);
      }
    }
    st.i0 = i0;
    st.activeCount = active;
    if (!any)
      return false;

    // palette only: which constant joints' model matrices are needed (those on the way
    // from an active joint up to its nearest active ancestor; the others are folded)
    if (folds && statusChanged) {
      std::uint8_t* needModel = &ctx.m_needModel[base];
      std::uint8_t* __restrict need = foldChanged; // as scratch here
      for (int j = 0; j < joints; ++j)
        need[j] = statuses[j] & kActive;
      for (int j = joints - 1; j > 0; --j)
        if (need[j] && parents[j] >= 0)
          need[parents[j]] = 1;
      for (int j = 0; j < joints; ++j)
        if (need[j] != needModel[j] || full) {
          needModel[j] = need[j];
          changed[j] = 1; // folded <-> computed from its parent
          firstChanged = std::min(firstChanged, j);
        }
    }
    // the folds below the joints that changed
    if (folds) {
      const std::uint8_t* needModel = &ctx.m_needModel[base];
      for (int j = firstChanged; j < joints; ++j) {
        const std::size_t i = base + static_cast<std::size_t>(j);
        const int p = parents[j];
        const bool redo = !needModel[j] && (changed[j] || (p >= firstChanged && (changed[p] || foldChanged[p])));
        foldChanged[j] = redo;
        if (!redo)
          continue;
        const std::size_t pi = base + static_cast<std::size_t>(p);
        if (p >= 0 && !needModel[p]) {
          ctx.m_anchor[i] = ctx.m_anchor[pi];
          mulAffine(glm::value_ptr(ctx.m_fold[pi]), glm::value_ptr(*ctx.m_constLocal[i]), glm::value_ptr(ctx.m_fold[i]));
        } else {
          ctx.m_anchor[i] = static_cast<std::int16_t>(p);
          ctx.m_fold[i] = *ctx.m_constLocal[i];
        }
        mulAffine(glm::value_ptr(ctx.m_fold[i]), glm::value_ptr(job.inverseBinds[static_cast<std::size_t>(j)]),
                  glm::value_ptr(ctx.m_foldPalette[i]));
      }
    }
    std::fill_n(changed, joints, 0);
    st.planValid = true;
    st.folding = job.folding;
    st.models = !job.out_models.empty();
    st.blendFrames = blendFrames;
    return true;
  }

  MLOD_RUNTIME_CLONES
  static void pose(const PoseEvaluatorJob& job, int c, double f, std::int32_t i0, float fraction, float levelWeight,
                   Scratch& scratch) {
    PoseEvaluatorContext& ctx = *job.context;
    const State& st = ctx.m_states[static_cast<std::size_t>(c)];
    const LodClip& clip = *st.clip;
    const int joints = ctx.m_joints;
    const std::size_t words = ctx.m_words;
    const std::size_t base = static_cast<std::size_t>(c) * static_cast<std::size_t>(joints);
    const std::uint64_t* activeSet = &ctx.m_activeSet[static_cast<std::size_t>(c) * words];
    float* __restrict soa = scratch.soa.data();
    float* __restrict locals = glm::value_ptr(scratch.locals[0]); // active slot k's local matrix: locals[16 k ...]
    const glm::quat* rotations = clip.rotations().data();
    const std::int32_t* rotationIndex = &ctx.m_rotationIndex[base];
    const std::int32_t* rotationStep = &ctx.m_rotationStep[base];
    const int count = st.activeCount;
    const int blocks = (count + kLanes - 1) / kLanes;
    const auto lane = [soa](int k) {
      const unsigned u = static_cast<unsigned>(k);
      return soa + (u / kLanes) * kBlockFloats + u % kLanes;
    };
    // the next lane after `b` (lane k): the next float, or the next block's first
    const auto next = [](float* b, int k) { return (k + 1) % kLanes ? b + 1 : b + 1 - kLanes + kBlockFloats; };

    // 1. gather the two rotations around f of every active joint
    const std::uint8_t* status = &ctx.m_status[base];
    std::int16_t* blending = scratch.blending.data(); // pairs (joint, lane)
    int k = 0, blendCount = 0;
    float* b = soa;
    forEachJoint(activeSet, words, [&](int j) {
      const glm::quat* p = rotations + (rotationIndex[j] + rotationStep[j] * i0);
      blending[2 * blendCount] = static_cast<std::int16_t>(j);
      blending[2 * blendCount + 1] = static_cast<std::int16_t>(k);
      blendCount += (status[j] & kBlend) ? 1 : 0;
      b[kAx * kLanes] = p[0].x;
      b[kAy * kLanes] = p[0].y;
      b[kAz * kLanes] = p[0].z;
      b[kAw * kLanes] = p[0].w;
      b[kBx * kLanes] = p[1].x;
      b[kBy * kLanes] = p[1].y;
      b[kBz * kLanes] = p[1].z;
      b[kBw * kLanes] = p[1].w;
      // translation straight into the local matrix; scale into the block
      const std::uint8_t flags = clip.flags(j);
      glm::vec3 translation = clip.staticTranslation(j);
      if (flags & LodClip::kTranslationAnimated) {
        const glm::vec3* track = clip.translationTrack(j);
        translation = track[i0] + (track[i0 + 1] - track[i0]) * fraction;
      }
      float* local = locals + 16 * static_cast<std::size_t>(k);
      local[12] = translation.x;
      local[13] = translation.y;
      local[14] = translation.z;
      glm::vec3 scale(1.0f);
      if (flags & LodClip::kScaled) {
        const glm::vec3* track = clip.scaleTrack(j);
        scale = track ? track[i0] + (track[i0 + 1] - track[i0]) * fraction : clip.staticScale(j);
      }
      b[kSx * kLanes] = scale.x;
      b[kSy * kLanes] = scale.y;
      b[kSz * kLanes] = scale.z;
      b = next(b, k++);
    });
    for (; k < blocks * kLanes; b = next(b, k++)) { // unused lanes: the identity
      b[kAx * kLanes] = b[kAy * kLanes] = b[kAz * kLanes] = b[kBx * kLanes] = b[kBy * kLanes] = b[kBz * kLanes] = 0.0f;
      b[kAw * kLanes] = b[kBw * kLanes] = b[kSx * kLanes] = b[kSy * kLanes] = b[kSz * kLanes] = 1.0f;
    }
    // 2. lerp, 8 joints at once
    for (int block = 0; block < blocks; ++block)
      lerpBlock(soa + static_cast<std::size_t>(block) * kBlockFloats, fraction);
    // 3. blend offsets of the few joints that resume (older offsets outermost), as products
    //    of unnormalised quaternions (each offset's nlerp normalisation is the final one's)
    const float inverseBlendFrames = job.blendFrames > 0 ? 1.0f / static_cast<float>(job.blendFrames) : 0.0f;
    for (int n = 0; n < blendCount; ++n) {
      const int j = blending[2 * n];
      const std::size_t i = base + static_cast<std::size_t>(j);
      b = lane(blending[2 * n + 1]);
      glm::quat q(b[kQw * kLanes], b[kQx * kLanes], b[kQy * kLanes], b[kQz * kLanes]);
      const LodClip::Cluster* clusters = clip.clusters(j).data();
      const int windows = ctx.m_windowCount[i];
      const int latest = ctx.m_windowLatest[i];
      if (windows > 0 && clusters[latest].last == i0) {
        // [last, last + 1) of the cluster it leaves: S starts from q(last), not the key
        const glm::quat& a = clusters[latest].lastRotation;
        q = glm::quat(a.w + (b[kBw * kLanes] - a.w) * fraction, a.x + (b[kBx * kLanes] - a.x) * fraction,
                      a.y + (b[kBy * kLanes] - a.y) * fraction, a.z + (b[kBz * kLanes] - a.z) * fraction);
      }
      for (int w = 0; w < windows; ++w) {
        const LodClip::Cluster& cluster = clusters[latest - w];
        const float weight = std::clamp(static_cast<float>(f - cluster.last) * inverseBlendFrames, 0.0f, 1.0f);
        q = lerpOffset(cluster.exitOffset, 1.0f - weight) * q;
      }
      if (status[j] & kWrap)
        q = lerpOffset(ctx.m_wrapOffset[i], 1.0f - std::min(static_cast<float>(f) * inverseBlendFrames, 1.0f)) * q;
      if (status[j] & kLevel)
        q = lerpOffset(ctx.m_levelOffset[i], levelWeight) * q;
      b[kQx * kLanes] = q.x;
      b[kQy * kLanes] = q.y;
      b[kQz * kLanes] = q.z;
      b[kQw * kLanes] = q.w;
    }
    // 4. rotation matrices, 8 joints at once, then into each active joint's local matrix
    for (int block = 0; block < blocks; ++block)
      matrixBlock(soa + static_cast<std::size_t>(block) * kBlockFloats);
    b = soa;
    for (k = 0; k < count; b = next(b, k++)) {
      float* local = locals + 16 * static_cast<std::size_t>(k);
      local[0] = b[kM00 * kLanes];
      local[1] = b[kM01 * kLanes];
      local[2] = b[kM02 * kLanes];
      local[4] = b[kM10 * kLanes];
      local[5] = b[kM11 * kLanes];
      local[6] = b[kM12 * kLanes];
      local[8] = b[kM20 * kLanes];
      local[9] = b[kM21 * kLanes];
      local[10] = b[kM22 * kLanes];
    }
    // 5. the hierarchy, parents first: the same two products for every joint whose model
    //    matrix is computed, whatever its status (no branch on it: statuses differ from
    //    character to character, and a mispredicted branch costs as much as a product)
    glm::mat4* models = job.out_models.empty() ? scratch.models.data() : &job.out_models[base];
    glm::mat4* palette = &job.out_palette[base];
    const std::int16_t* parents = job.parents.data();
    const glm::mat4* inverseBinds = job.inverseBinds.data();
    const std::int16_t* anchor = &ctx.m_anchor[base];
    const std::uint8_t* needModel = &ctx.m_needModel[base];
    const glm::mat4* foldPalette = &ctx.m_foldPalette[base];
    const glm::mat4* localCopy = &ctx.m_local[base];
    const bool folds = job.folding && job.out_models.empty();
    const float* active = locals;
    for (int j = 0; j < joints; ++j) {
      const bool isActive = status[j] & kActive;
      // (a constant joint's matrix, or the next active one's: a select, not a branch)
      const float* local = isActive ? active : glm::value_ptr(localCopy[j]);
      active += isActive ? 16 : 0;
      if (folds && !isActive && !needModel[j]) {
        // folded: the palette straight from the nearest ancestor with a model matrix
        const int a = anchor[j];
        if (a >= 0)
          mulAffine(glm::value_ptr(models[a]), glm::value_ptr(foldPalette[j]), glm::value_ptr(palette[j]));
        else
          palette[j] = foldPalette[j];
        continue;
      }
      float* model = glm::value_ptr(models[j]);
      const int p = parents[j];
      if (p >= 0)
        mulAffine(glm::value_ptr(models[p]), local, model);
      else
        std::memcpy(model, local, sizeof(glm::mat4));
      mulAffine(model, glm::value_ptr(inverseBinds[j]), glm::value_ptr(palette[j]));
    }
  }
};

void PoseEvaluatorContext::resize(int characters, int joints, int threads) {
  characters = std::max(characters, 0);
  joints = std::max(joints, 0);
  threads = std::max(threads, 1);
  m_joints = joints;
  m_blocks = (static_cast<std::size_t>(joints) + kLanes - 1) / kLanes;
  m_words = (static_cast<std::size_t>(joints) + 63) / 64;
  const std::size_t n = static_cast<std::size_t>(characters) * static_cast<std::size_t>(joints);
  m_states.assign(static_cast<std::size_t>(characters), CharacterState{});
  m_cursor.assign(n, -1);
  m_status.assign(n, 0);
  m_rotationIndex.assign(n, 0);
  m_rotationStep.assign(n, 0);
  m_windowLatest.assign(n, -1);
  m_windowCount.assign(n, 0);
  m_constLocal.assign(n, nullptr);
  m_local.assign(n, glm::mat4(1.0f));
  m_anchor.assign(n, -1);
  m_needModel.assign(n, 1);
  m_activeSet.assign(static_cast<std::size_t>(characters) * m_words, 0);
  m_fold.assign(n, glm::mat4(1.0f));
  m_foldPalette.assign(n, glm::mat4(1.0f));
  m_levelOffset.assign(n, glm::quat(1.0f, 0.0f, 0.0f, 0.0f));
  m_wrapOffset.assign(n, glm::quat(1.0f, 0.0f, 0.0f, 0.0f));
  m_scratch.clear();
  m_scratch.resize(static_cast<std::size_t>(threads));
  for (Scratch& scratch : m_scratch) {
    scratch.soa.assign(kBlockFloats * std::max<std::size_t>(m_blocks, 1), 0.0f);
    scratch.models.assign(static_cast<std::size_t>(joints), glm::mat4(1.0f));
    scratch.locals.assign(std::max(joints, 1), glm::mat4(1.0f)); // rows 3 stay 0 0 0 1
    scratch.blending.assign(2 * static_cast<std::size_t>(joints), 0);
    scratch.changed.assign(static_cast<std::size_t>(joints), 0);
    scratch.foldChanged.assign(static_cast<std::size_t>(joints), 0);
  }
  m_parentsSeen = nullptr;
  m_inverseBindsSeen = nullptr;
}

void PoseEvaluatorContext::reset() {
  for (int c = 0; c < characterCount(); ++c)
    reset(c);
}

void PoseEvaluatorContext::reset(int character) {
  m_states[static_cast<std::size_t>(character)] = CharacterState{};
  std::fill_n(m_cursor.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(character) * m_joints), m_joints,
              -1);
}

std::size_t PoseEvaluatorContext::bytesPerCharacter() const {
  const std::size_t perJoint = 5 * sizeof(std::int32_t) + 2 * sizeof(std::uint8_t) + sizeof(const glm::mat4*) +
                               sizeof(std::int16_t) + 3 * sizeof(glm::mat4) + 2 * sizeof(glm::quat);
  return sizeof(CharacterState) + perJoint * static_cast<std::size_t>(m_joints) + m_words * sizeof(std::uint64_t);
}

std::size_t PoseEvaluatorContext::byteSize() const {
  std::size_t scratch = 0;
  for (const Scratch& s : m_scratch)
    scratch += sizeof(Scratch) + s.soa.size() * sizeof(float) + (s.models.size() + s.locals.size()) * sizeof(glm::mat4) +
               s.blending.size() * sizeof(std::int16_t) + s.changed.size() + s.foldChanged.size();
  return sizeof(*this) + bytesPerCharacter() * m_states.size() + scratch;
}

bool PoseEvaluatorJob::validate() const {
  if (!context)
    return false;
  const std::size_t joints = parents.size();
  if (joints < 1 || joints > 32767)
    return false;
  for (std::size_t j = 0; j < joints; ++j)
    if (parents[j] < -1 || parents[j] >= static_cast<std::int32_t>(j))
      return false;
  if (inverseBinds.size() != joints)
    return false;
  for (const glm::mat4& m : inverseBinds)
    if (m[0][3] != 0.0f || m[1][3] != 0.0f || m[2][3] != 0.0f || m[3][3] != 1.0f)
      return false;
  const std::size_t characters = clips.size();
  if (times.size() != characters)
    return false;
  if (context->jointCount() != static_cast<int>(joints) ||
      static_cast<std::size_t>(context->characterCount()) < characters)
    return false;
  if (context->threadCount() < (pool ? pool->threadCount() : 1))
    return false;
  if (blendFrames < 0 || blendFrames > 10000)
    return false;
  if (out_palette.size() != characters * joints || (!out_models.empty() && out_models.size() != characters * joints))
    return false;
  for (std::size_t c = 0; c < characters; ++c) {
    const LodClip* clip = clips[c];
    if (!clip || clip->jointCount() != static_cast<int>(joints))
      return false;
    const double t = times[c];
    if (!std::isfinite(t) || t < 0.0)
      return false;
    if (!clip->looping() && t * clip->fps() > clip->frameCount() - 1 + 1e-6)
      return false;
  }
  return true;
}

bool PoseEvaluatorJob::run() const {
  if (!validate())
    return false;
  PoseEvaluatorContext& ctx = *context;
  if (ctx.m_parentsSeen != parents.data() || ctx.m_inverseBindsSeen != inverseBinds.data()) {
    for (PoseEvaluatorContext::CharacterState& state : ctx.m_states)
      state.planValid = false;
    ctx.m_parentsSeen = parents.data();
    ctx.m_inverseBindsSeen = inverseBinds.data();
  }
  for (PoseEvaluatorContext::Scratch& scratch : ctx.m_scratch) {
    scratch.sampled = 0;
    scratch.rebuilds = 0;
  }
  const int characters = static_cast<int>(clips.size());
  const int threads = pool ? pool->threadCount() : 1;
  if (threads > 1) {
    const int grain = std::max(1, characters / (threads * 16));
    pool->run(characters, grain, &PoseEvaluation::runRange, const_cast<PoseEvaluatorJob*>(this));
  } else {
    PoseEvaluation::runRange(const_cast<PoseEvaluatorJob*>(this), 0, characters, 0);
  }
  ctx.m_lastSampled = 0;
  ctx.m_lastRebuilds = 0;
  for (const PoseEvaluatorContext::Scratch& scratch : ctx.m_scratch) {
    ctx.m_lastSampled += scratch.sampled;
    ctx.m_lastRebuilds += scratch.rebuilds;
  }
  return true;
}

} // namespace mlod
