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

// Structure-of-arrays buffers of the active joints of one character.
enum SoaArray {
  kAx, kAy, kAz, kAw, // rotation at the frame before
  kBx, kBy, kBz, kBw, // rotation at the frame after
  kQx, kQy, kQz, kQw, // the interpolated rotation
  kM00, kM01, kM02, kM10, kM11, kM12, kM20, kM21, kM22, // local matrix columns (rotation x scale)
  kTx, kTy, kTz,       // local translation
  kSx, kSy, kSz,       // local scale
  kSoaArrays
};

// Joint status in a plan: bit 0 = active (its local matrix is computed this frame);
// constant joints (frozen or static) take a precomputed local matrix.
constexpr std::uint8_t kActive = 1;
constexpr std::uint8_t kBlend = 2; // its rotation gets blend offsets (implies active)
constexpr std::uint8_t kHold = 4;  // inside [last, last + 1) of a cluster it leaves: S reads q(last), not the key
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

// out = a x the local matrix of active slot k in the SoA buffers.
inline void mulLocal(const float* __restrict a, const float* __restrict soa, std::size_t stride, int k,
                     float* __restrict out) {
  const auto at = [&](int array) { return soa[static_cast<std::size_t>(array) * stride + static_cast<std::size_t>(k)]; };
  const v4 a0 = load4(a), a1 = load4(a + 4), a2 = load4(a + 8), a3 = load4(a + 12);
  store4(out, a0 * at(kM00) + a1 * at(kM01) + a2 * at(kM02));
  store4(out + 4, a0 * at(kM10) + a1 * at(kM11) + a2 * at(kM12));
  store4(out + 8, a0 * at(kM20) + a1 * at(kM21) + a2 * at(kM22));
  store4(out + 12, a0 * at(kTx) + a1 * at(kTy) + a2 * at(kTz) + a3);
}

inline void setLocal(const float* __restrict soa, std::size_t stride, int k, float* __restrict out) {
  const auto at = [&](int array) { return soa[static_cast<std::size_t>(array) * stride + static_cast<std::size_t>(k)]; };
  const float m[16] = {at(kM00), at(kM01), at(kM02), 0.0f, at(kM10), at(kM11), at(kM12), 0.0f,
                       at(kM20), at(kM21), at(kM22), 0.0f, at(kTx),  at(kTy),  at(kTz),  1.0f};
  std::memcpy(out, m, sizeof m);
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

} // namespace

struct PoseEvaluation {
  using State = PoseEvaluatorContext::CharacterState;
  using Scratch = PoseEvaluatorContext::Scratch;

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
    if (full || i0 < st.lo || i0 > st.hi) {
      rebuild(job, c, i0, full, scratch);
      ++scratch.rebuilds;
    }
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

  // Makes the plan of character c hold at frame i0: re-reads the joints whose own range
  // does not hold i0 (every joint when `full`), then refolds below the ones that changed.
  static void rebuild(const PoseEvaluatorJob& job, int c, std::int32_t i0, bool full, Scratch& scratch) {
    PoseEvaluatorContext& ctx = *job.context;
    State& st = ctx.m_states[static_cast<std::size_t>(c)];
    const LodClip& clip = *st.clip;
    const int joints = ctx.m_joints;
    const int blendFrames = job.blendFrames;
    const std::size_t base = static_cast<std::size_t>(c) * static_cast<std::size_t>(joints);
    std::uint8_t* changed = scratch.changed.data();

    if (full && st.wrapWindow)
      for (int j = 0; j < joints; ++j)
        ctx.m_wrapOffset[base + static_cast<std::size_t>(j)] =
            positiveW(clip.rotationAt(j, clip.frameCount() - 1, blendFrames) *
                      glm::inverse(clip.rotationAt(j, 0.0, blendFrames)));

    for (int j = 0; j < joints; ++j) {
      const std::size_t i = base + static_cast<std::size_t>(j);
      if (!full && i0 >= ctx.m_jointLo[i] && i0 <= ctx.m_jointHi[i]) {
        changed[j] = 0;
        continue;
      }
      const std::uint8_t oldStatus = ctx.m_status[i];
      const glm::mat4* oldLocal = ctx.m_constLocal[i];
      const std::uint8_t flags = clip.flags(j);
      bool constant = false;
      const glm::mat4* local = nullptr;
      std::int32_t lo = INT_MIN, hi = INT_MAX;
      std::uint8_t status = 0;
      std::int32_t rotationIndex = 0, rotationStep = 0, windowLatest = -1, windowCount = 0;
      if (!(flags & LodClip::kRotationAnimated)) {
        rotationIndex = clip.staticRotationPair(j);
        local = &clip.staticLocal(j);
        constant = !(flags & kAnimatedTranslationOrScale);
      } else {
        const std::span<const LodClip::Segment> segments = clip.segments(j);
        int s = ctx.m_cursor[i];
        if (s < 0) {
          s = clip.findSegment(j, i0);
        } else {
          // usually the next segment; far jumps (a wrap, a scrub) search
          int steps = 0;
          while (i0 > segments[static_cast<std::size_t>(s)].last && ++steps < 4)
            ++s;
          while (i0 < segments[static_cast<std::size_t>(s)].first && ++steps < 4)
            --s;
          if (i0 < segments[static_cast<std::size_t>(s)].first || i0 > segments[static_cast<std::size_t>(s)].last)
            s = clip.findSegment(j, i0);
        }
        ctx.m_cursor[i] = s;
        const LodClip::Segment& segment = segments[static_cast<std::size_t>(s)];
        const std::span<const LodClip::Cluster> clusters = clip.clusters(j);
        lo = segment.first;
        hi = segment.last;
        if (blendFrames > 0) {
          int cc = segment.previous;
          for (; cc >= 0 && clusters[static_cast<std::size_t>(cc)].last + blendFrames > i0; --cc) {
            ++windowCount;
            hi = std::min(hi, clusters[static_cast<std::size_t>(cc)].last + blendFrames - 1);
          }
          if (cc >= 0)
            lo = std::max(lo, clusters[static_cast<std::size_t>(cc)].last + blendFrames);
          windowLatest = segment.previous;
          if (segment.cluster < 0 && segment.previous >= 0 &&
              clusters[static_cast<std::size_t>(segment.previous)].last == i0) {
            status |= kHold;
            hi = std::min(hi, i0);
          }
        }
        if (segment.cluster >= 0) {
          const LodClip::Cluster& cluster = clusters[static_cast<std::size_t>(segment.cluster)];
          rotationIndex = cluster.keyPair;
          local = &cluster.keyLocal;
          constant = windowCount == 0 && !(flags & kAnimatedTranslationOrScale);
        } else {
          rotationIndex = segment.rotation - segment.first;
          rotationStep = 1;
        }
      }
      if (st.levelBlend && !isIdentity(ctx.m_levelOffset[i])) {
        status |= kLevel;
        constant = false;
      }
      if (st.wrapWindow && !isIdentity(ctx.m_wrapOffset[i])) {
        status |= kWrap;
        constant = false;
      }
      if (windowCount > 0 || (status & (kHold | kLevel | kWrap)))
        status |= kBlend;
      if (!constant)
        status |= kActive;
      ctx.m_status[i] = status;
      ctx.m_constLocal[i] = constant ? local : nullptr;
      ctx.m_jointLo[i] = lo;
      ctx.m_jointHi[i] = hi;
      ctx.m_rotationIndex[i] = rotationIndex;
      ctx.m_rotationStep[i] = rotationStep;
      ctx.m_windowLatest[i] = windowLatest;
      ctx.m_windowCount[i] = windowCount;
      changed[j] = full || ((oldStatus ^ status) & kActive) || (constant && oldLocal != local);
    }

    // the range of frames the plan holds for, and the lists
    std::int32_t lo = INT_MIN, hi = INT_MAX;
    std::int32_t active = 0, blending = 0;
    for (int j = 0; j < joints; ++j) {
      const std::size_t i = base + static_cast<std::size_t>(j);
      lo = std::max(lo, ctx.m_jointLo[i]);
      hi = std::min(hi, ctx.m_jointHi[i]);
      if (ctx.m_status[i] & kActive) {
        ctx.m_slot[i] = static_cast<std::int16_t>(active);
        ctx.m_active[base + static_cast<std::size_t>(active++)] = static_cast<std::int16_t>(j);
        if (ctx.m_status[i] & kBlend)
          ctx.m_blending[base + static_cast<std::size_t>(blending++)] = static_cast<std::int16_t>(j);
      }
    }
    st.lo = lo;
    st.hi = hi;
    st.activeCount = active;
    st.blendCount = blending;

    if (job.folding) {
      // a frozen joint's model matrix is needed for output, or by an active child
      std::uint8_t* needModel = &ctx.m_needModel[base];
      std::fill_n(needModel, joints, job.out_models.empty() ? 0 : 1);
      for (int j = 1; j < joints; ++j) {
        const int p = job.parents[static_cast<std::size_t>(j)];
        if (p >= 0 && (ctx.m_status[base + static_cast<std::size_t>(j)] & kActive))
          needModel[p] = 1;
      }
      std::uint8_t* foldChanged = scratch.foldChanged.data();
      for (int j = 0; j < joints; ++j) {
        const std::size_t i = base + static_cast<std::size_t>(j);
        foldChanged[j] = 0;
        if (ctx.m_status[i] & kActive)
          continue;
        const int p = job.parents[static_cast<std::size_t>(j)];
        if (!changed[j] && !(p >= 0 && (changed[p] || foldChanged[p])))
          continue;
        foldChanged[j] = 1;
        const std::size_t pi = base + static_cast<std::size_t>(p);
        const bool parentConstant = p >= 0 && !(ctx.m_status[pi] & kActive);
        if (parentConstant) {
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
    st.planValid = true;
    st.folding = job.folding;
    st.models = !job.out_models.empty();
    st.blendFrames = blendFrames;
  }

  MLOD_RUNTIME_CLONES
  static void pose(const PoseEvaluatorJob& job, int c, double f, std::int32_t i0, float fraction, float levelWeight,
                   Scratch& scratch) {
    PoseEvaluatorContext& ctx = *job.context;
    const State& st = ctx.m_states[static_cast<std::size_t>(c)];
    const LodClip& clip = *st.clip;
    const int joints = ctx.m_joints;
    const std::size_t base = static_cast<std::size_t>(c) * static_cast<std::size_t>(joints);
    const std::size_t stride = ctx.m_stride;
    float* __restrict soa = scratch.soa.data();
    float* __restrict ax = soa + kAx * stride;
    float* __restrict ay = soa + kAy * stride;
    float* __restrict az = soa + kAz * stride;
    float* __restrict aw = soa + kAw * stride;
    float* __restrict bx = soa + kBx * stride;
    float* __restrict by = soa + kBy * stride;
    float* __restrict bz = soa + kBz * stride;
    float* __restrict bw = soa + kBw * stride;
    float* __restrict qx = soa + kQx * stride;
    float* __restrict qy = soa + kQy * stride;
    float* __restrict qz = soa + kQz * stride;
    float* __restrict qw = soa + kQw * stride;
    float* __restrict tx = soa + kTx * stride;
    float* __restrict ty = soa + kTy * stride;
    float* __restrict tz = soa + kTz * stride;
    float* __restrict sx = soa + kSx * stride;
    float* __restrict sy = soa + kSy * stride;
    float* __restrict sz = soa + kSz * stride;
    const glm::quat* rotations = clip.rotations().data();
    const std::int16_t* active = &ctx.m_active[base];
    const std::int32_t* rotationIndex = &ctx.m_rotationIndex[base];
    const std::int32_t* rotationStep = &ctx.m_rotationStep[base];
    const int count = st.activeCount;

    // 1. gather the two rotations around f of every active joint, its translation and scale
    for (int k = 0; k < count; ++k) {
      const int j = active[k];
      const glm::quat* p = rotations + (rotationIndex[j] + rotationStep[j] * i0);
      ax[k] = p[0].x;
      ay[k] = p[0].y;
      az[k] = p[0].z;
      aw[k] = p[0].w;
      bx[k] = p[1].x;
      by[k] = p[1].y;
      bz[k] = p[1].z;
      bw[k] = p[1].w;
      glm::vec3 translation = clip.staticTranslation(j);
      if (const glm::vec3* track = clip.translationTrack(j))
        translation = track[i0] + (track[i0 + 1] - track[i0]) * fraction;
      tx[k] = translation.x;
      ty[k] = translation.y;
      tz[k] = translation.z;
      glm::vec3 scale = clip.staticScale(j);
      if (const glm::vec3* track = clip.scaleTrack(j))
        scale = track[i0] + (track[i0 + 1] - track[i0]) * fraction;
      sx[k] = scale.x;
      sy[k] = scale.y;
      sz[k] = scale.z;
    }
    // 2. nlerp, every active joint at once (stored rotations are sign-aligned)
    for (int k = 0; k < count; ++k) {
      const float x = ax[k] + (bx[k] - ax[k]) * fraction;
      const float y = ay[k] + (by[k] - ay[k]) * fraction;
      const float z = az[k] + (bz[k] - az[k]) * fraction;
      const float w = aw[k] + (bw[k] - aw[k]) * fraction;
      const float inverse = 1.0f / std::sqrt(x * x + y * y + z * z + w * w);
      qx[k] = x * inverse;
      qy[k] = y * inverse;
      qz[k] = z * inverse;
      qw[k] = w * inverse;
    }
    // 3. blend offsets of the few joints that resume (older offsets outermost)
    const int blendFrames = job.blendFrames;
    for (int b = 0; b < st.blendCount; ++b) {
      const int j = ctx.m_blending[base + static_cast<std::size_t>(b)];
      const std::size_t i = base + static_cast<std::size_t>(j);
      const int k = ctx.m_slot[i];
      const std::uint8_t status = ctx.m_status[i];
      glm::quat q(qw[k], qx[k], qy[k], qz[k]);
      const std::span<const LodClip::Cluster> clusters = clip.clusters(j);
      if (status & kHold) {
        const glm::quat& a = clusters[static_cast<std::size_t>(ctx.m_windowLatest[i])].lastRotation;
        q = glm::normalize(glm::quat(a.w + (bw[k] - a.w) * fraction, a.x + (bx[k] - a.x) * fraction,
                                     a.y + (by[k] - a.y) * fraction, a.z + (bz[k] - a.z) * fraction));
      }
      if (ctx.m_windowCount[i] > 0) {
        for (int n = 0, cc = ctx.m_windowLatest[i]; n < ctx.m_windowCount[i]; ++n, --cc) {
          const LodClip::Cluster& cluster = clusters[static_cast<std::size_t>(cc)];
          const double w = std::clamp((f - cluster.last) / blendFrames, 0.0, 1.0);
          q = scaleOffset(cluster.exitOffset, static_cast<float>(1.0 - w)) * q;
        }
      }
      if (status & kWrap)
        q = scaleOffset(ctx.m_wrapOffset[i], static_cast<float>(1.0 - std::min(f / blendFrames, 1.0))) * q;
      if (status & kLevel)
        q = scaleOffset(ctx.m_levelOffset[i], levelWeight) * q;
      qx[k] = q.x;
      qy[k] = q.y;
      qz[k] = q.z;
      qw[k] = q.w;
    }
    // 4. local matrices (glm::mat3_cast, columns scaled), every active joint at once
    {
      float* __restrict m00 = soa + kM00 * stride;
      float* __restrict m01 = soa + kM01 * stride;
      float* __restrict m02 = soa + kM02 * stride;
      float* __restrict m10 = soa + kM10 * stride;
      float* __restrict m11 = soa + kM11 * stride;
      float* __restrict m12 = soa + kM12 * stride;
      float* __restrict m20 = soa + kM20 * stride;
      float* __restrict m21 = soa + kM21 * stride;
      float* __restrict m22 = soa + kM22 * stride;
      for (int k = 0; k < count; ++k) {
        const float x = qx[k], y = qy[k], z = qz[k], w = qw[k];
        const float xx = x * x, yy = y * y, zz = z * z, xy = x * y, xz = x * z, yz = y * z, wx = w * x, wy = w * y,
                    wz = w * z;
        m00[k] = (1.0f - 2.0f * (yy + zz)) * sx[k];
        m01[k] = 2.0f * (xy + wz) * sx[k];
        m02[k] = 2.0f * (xz - wy) * sx[k];
        m10[k] = 2.0f * (xy - wz) * sy[k];
        m11[k] = (1.0f - 2.0f * (xx + zz)) * sy[k];
        m12[k] = 2.0f * (yz + wx) * sy[k];
        m20[k] = 2.0f * (xz + wy) * sz[k];
        m21[k] = 2.0f * (yz - wx) * sz[k];
        m22[k] = (1.0f - 2.0f * (xx + yy)) * sz[k];
      }
    }
    // 5. the hierarchy, parents first
    glm::mat4* models = job.out_models.empty() ? scratch.models.data() : &job.out_models[base];
    glm::mat4* palette = &job.out_palette[base];
    const std::int16_t* parents = job.parents.data();
    const glm::mat4* inverseBinds = job.inverseBinds.data();
    const std::uint8_t* status = &ctx.m_status[base];
    const std::int16_t* anchor = &ctx.m_anchor[base];
    const std::uint8_t* needModel = &ctx.m_needModel[base];
    const glm::mat4* fold = &ctx.m_fold[base];
    const glm::mat4* foldPalette = &ctx.m_foldPalette[base];
    const glm::mat4* const* constLocal = &ctx.m_constLocal[base];
    const bool folding = job.folding;
    int k = 0;
    for (int j = 0; j < joints; ++j) {
      float* model = glm::value_ptr(models[j]);
      if (status[j] & kActive) {
        const int p = parents[j];
        if (p >= 0)
          mulLocal(glm::value_ptr(models[p]), soa, stride, k, model);
        else
          setLocal(soa, stride, k, model);
        mulAffine(model, glm::value_ptr(inverseBinds[j]), glm::value_ptr(palette[j]));
        ++k;
      } else if (folding) {
        const int a = anchor[j];
        if (a >= 0) {
          if (needModel[j])
            mulAffine(glm::value_ptr(models[a]), glm::value_ptr(fold[j]), model);
          mulAffine(glm::value_ptr(models[a]), glm::value_ptr(foldPalette[j]), glm::value_ptr(palette[j]));
        } else {
          models[j] = fold[j];
          palette[j] = foldPalette[j];
        }
      } else {
        const int p = parents[j];
        if (p >= 0)
          mulAffine(glm::value_ptr(models[p]), glm::value_ptr(*constLocal[j]), model);
        else
          models[j] = *constLocal[j];
        mulAffine(model, glm::value_ptr(inverseBinds[j]), glm::value_ptr(palette[j]));
      }
    }
  }
};

void PoseEvaluatorContext::resize(int characters, int joints, int threads) {
  characters = std::max(characters, 0);
  joints = std::max(joints, 0);
  threads = std::max(threads, 1);
  m_joints = joints;
  m_stride = (static_cast<std::size_t>(joints) + 15) / 16 * 16;
  const std::size_t n = static_cast<std::size_t>(characters) * static_cast<std::size_t>(joints);
  m_states.assign(static_cast<std::size_t>(characters), CharacterState{});
  m_cursor.assign(n, -1);
  m_jointLo.assign(n, 0);
  m_jointHi.assign(n, -1);
  m_status.assign(n, 0);
  m_rotationIndex.assign(n, 0);
  m_rotationStep.assign(n, 0);
  m_windowLatest.assign(n, -1);
  m_windowCount.assign(n, 0);
  m_constLocal.assign(n, nullptr);
  m_anchor.assign(n, -1);
  m_slot.assign(n, 0);
  m_active.assign(n, 0);
  m_blending.assign(n, 0);
  m_needModel.assign(n, 0);
  m_fold.assign(n, glm::mat4(1.0f));
  m_foldPalette.assign(n, glm::mat4(1.0f));
  m_levelOffset.assign(n, glm::quat(1.0f, 0.0f, 0.0f, 0.0f));
  m_wrapOffset.assign(n, glm::quat(1.0f, 0.0f, 0.0f, 0.0f));
  m_scratch.clear();
  m_scratch.resize(static_cast<std::size_t>(threads));
  for (Scratch& scratch : m_scratch) {
    scratch.soa.assign(kSoaArrays * m_stride, 0.0f);
    scratch.models.assign(static_cast<std::size_t>(joints), glm::mat4(1.0f));
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
  const std::size_t perJoint = 6 * sizeof(std::int32_t) + 2 * sizeof(std::uint8_t) + sizeof(const glm::mat4*) +
                               4 * sizeof(std::int16_t) + 2 * sizeof(glm::mat4) + 2 * sizeof(glm::quat);
  return sizeof(CharacterState) + perJoint * static_cast<std::size_t>(m_joints);
}

std::size_t PoseEvaluatorContext::byteSize() const {
  std::size_t scratch = 0;
  for (const Scratch& s : m_scratch)
    scratch += sizeof(Scratch) + s.soa.size() * sizeof(float) + s.models.size() * sizeof(glm::mat4) +
               s.changed.size() + s.foldChanged.size();
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
