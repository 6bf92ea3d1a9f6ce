// The crowd pose evaluator: per character, the joints that move are decoded from the clip's
// compressed streams (two entries, nlerped or lerped) into the character's pose, a joint
// frozen in a cluster keeps the key it decoded when the cluster began, the few joints that
// blend (a loop wrap, a level change) get their offsets, and the hierarchy is walked once.
#include "runtime/pose_evaluator.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <glm/gtc/type_ptr.hpp>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

// The hot path is also compiled for x86-64-v3 (AVX2, FMA) and picked at load time.
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__)) && !defined(MLOD_NO_TARGET_CLONES)
#define MLOD_RUNTIME_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define MLOD_RUNTIME_CLONES
#endif

namespace mlod {

namespace {

constexpr int kLanes = LodClip::kLanes;
constexpr std::size_t kLocalBlock = static_cast<std::size_t>(kLanes) * LodClip::kLocalArrays;
// Arrays of a local matrix in lane layout (LodClip::laneOffset()).
enum LocalArray { kM00, kM01, kM02, kM10, kM11, kM12, kM20, kM21, kM22, kTx, kTy, kTz };
// A character's pose (PoseEvaluatorContext::m_pose): per joint its rotation (lerped, of
// any non-zero length), scale and translation, blocks of 8 joints (joint j at poseOffset(j)).
enum PoseArray { kAx, kAy, kAz, kAw, kSx, kSy, kSz, kPx, kPy, kPz, kPoseArrays };
constexpr std::size_t kPoseBlock = static_cast<std::size_t>(kLanes) * kPoseArrays;

inline std::size_t poseOffset(int j) {
  const std::size_t u = static_cast<std::size_t>(j);
  return (u / kLanes) * kPoseBlock + u % kLanes;
}
inline std::size_t poseBlocks(int joints) { return std::max<std::size_t>((static_cast<std::size_t>(joints) + kLanes - 1) / kLanes, 1); }

typedef float v4 __attribute__((vector_size(16)));

inline v4 load4(const float* p) {
  v4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
inline void store4(float* p, v4 v) {
  std::memcpy(p, &v, sizeof v);
}
// out = a x L for an affine 4x4 matrix a (column-major) and a local matrix L in lane layout.
inline void mulLane(const float* __restrict a, const float* __restrict l, float* __restrict out) {
  const v4 a0 = load4(a), a1 = load4(a + 4), a2 = load4(a + 8), a3 = load4(a + 12);
  store4(out, a0 * l[kM00 * kLanes] + a1 * l[kM01 * kLanes] + a2 * l[kM02 * kLanes]);
  store4(out + 4, a0 * l[kM10 * kLanes] + a1 * l[kM11 * kLanes] + a2 * l[kM12 * kLanes]);
  store4(out + 8, a0 * l[kM20 * kLanes] + a1 * l[kM21 * kLanes] + a2 * l[kM22 * kLanes]);
  store4(out + 12, a0 * l[kTx * kLanes] + a1 * l[kTy * kLanes] + a2 * l[kTz * kLanes] + a3);
}

// out = a x b for affine 4x4 matrices (column-major, bottom row 0 0 0 1; b's is not read).
inline void mulAffine(const float* __restrict a, const float* __restrict b, float* __restrict out) {
  const v4 a0 = load4(a), a1 = load4(a + 4), a2 = load4(a + 8), a3 = load4(a + 12);
  store4(out, a0 * b[0] + a1 * b[1] + a2 * b[2]);
  store4(out + 4, a0 * b[4] + a1 * b[5] + a2 * b[6]);
  store4(out + 8, a0 * b[8] + a1 * b[9] + a2 * b[10]);
  store4(out + 12, a0 * b[12] + a1 * b[13] + a2 * b[14] + a3);
}

// Local matrices of a block's 8 joints from their pose: the rotation of any non-zero length
// (glm::mat3_cast of the normalised quaternion: 2 becomes 2 / |q|^2, so that lerped
// rotations and blend offsets multiplied into them need no normalisation of their own),
// scale and translation.
template <bool Scaled> inline void matrixBlock(const float* __restrict s, float* __restrict l) {
  for (int i = 0; i < kLanes; ++i) {
    const float x = s[kAx * kLanes + i], y = s[kAy * kLanes + i], z = s[kAz * kLanes + i], w = s[kAw * kLanes + i];
    const float two = 2.0f / (x * x + y * y + z * z + w * w);
    const float xt = x * two, yt = y * two, zt = z * two;
    const float xx = x * xt, yy = y * yt, zz = z * zt, xy = x * yt, xz = x * zt, yz = y * zt, wx = w * xt, wy = w * yt,
                wz = w * zt;
    float sx = 1.0f, sy = 1.0f, sz = 1.0f;
    if constexpr (Scaled) {
      sx = s[kSx * kLanes + i];
      sy = s[kSy * kLanes + i];
      sz = s[kSz * kLanes + i];
    }
    l[kM00 * kLanes + i] = (1.0f - (yy + zz)) * sx;
    l[kM01 * kLanes + i] = (xy + wz) * sx;
    l[kM02 * kLanes + i] = (xz - wy) * sx;
    l[kM10 * kLanes + i] = (xy - wz) * sy;
    l[kM11 * kLanes + i] = (1.0f - (xx + zz)) * sy;
    l[kM12 * kLanes + i] = (yz + wx) * sy;
    l[kM20 * kLanes + i] = (xz + wy) * sz;
    l[kM21 * kLanes + i] = (yz - wx) * sz;
    l[kM22 * kLanes + i] = (1.0f - (xx + yy)) * sz;
  }
  // the translations: three whole arrays, in the same order in both layouts
  static_assert(kTy == kTx + 1 && kTz == kTx + 2 && kPy == kPx + 1 && kPz == kPx + 2);
  std::memcpy(l + kTx * kLanes, s + kPx * kLanes, 3 * kLanes * sizeof(float));
}

// nlerp(identity, offset, weight) before normalisation: (1 - weight) identity + weight offset.
inline glm::quat lerpOffset(const glm::quat& offset, float weight) {
  return glm::quat(1.0f - weight + weight * offset.w, weight * offset.x, weight * offset.y, weight * offset.z);
}

// An offset below float resolution changes nothing: the joint need not blend.
bool isIdentity(const glm::quat& q) {
  return std::abs(q.x) + std::abs(q.y) + std::abs(q.z) <= 1e-7f;
}

// A looping clip's wrap offset of `joint`: the jump from its last frame's rotation to its
// first's, which decays over the first N frames of every later period.
glm::quat wrapOffset(const LodClip& clip, int joint) {
  return positiveW(clip.rotationAt(joint, clip.frameCount() - 1) * glm::inverse(clip.rotationAt(joint, 0.0)));
}

// The rotation of `joint` that `clip` shows at `seconds` without level blending: M'
// with its unfreeze blends and, in a wrap window, the wrap offset.
glm::quat shownRotation(const LodClip& clip, int joint, double seconds, int blendFrames) {
  std::int64_t loop = 0;
  const double f = clip.framePosition(seconds, &loop);
  glm::quat q = clip.rotationAt(joint, f);
  std::int32_t i0 = 0;
  float fraction = 0.0f;
  clip.split(f, i0, fraction);
  if (blendFrames > 0 && clip.looping() && loop >= 1 && i0 < blendFrames) {
    const glm::quat wrap = wrapOffset(clip, joint);
    q = scaleOffset(wrap, static_cast<float>(1.0 - std::min(f / blendFrames, 1.0))) * q;
  }
  return q;
}

const glm::mat4 kIdentity(1.0f);

// The hierarchy pass of one character, parents first: the same two products for every joint
// (model = parent's model x local, palette = model x inverse bind), its local matrix in lane
// layout (LodClip::laneOffset()). Joint 0 is a root.
struct Hierarchy {
  const float* locals;
  const std::int16_t* parents;
  const float* inverseBinds; // column-major 4x4 per joint
  const float* splat;        // inverse binds as AVX operands (PoseEvaluatorContext::m_splat)
  float* models;
  float* palette;
  int joints;

  const float* local(int j) const { return locals + LodClip::laneOffset(static_cast<std::uint32_t>(j)); }
  const float* parent(int j, bool singleRoot) const {
    const int p = parents[j];
    return j > 0 && (singleRoot || p >= 0) ? models + 16 * p : glm::value_ptr(kIdentity);
  }
};

template <bool SingleRoot> void hierarchyBase(const Hierarchy& h) {
  mulLane(glm::value_ptr(kIdentity), h.local(0), h.models);
  mulAffine(h.models, h.inverseBinds, h.palette);
  for (int j = 1; j < h.joints; ++j) {
    float* model = h.models + 16 * j;
    mulLane(h.parent(j, SingleRoot), h.local(j), model);
    mulAffine(model, h.inverseBinds + 16 * j, h.palette + 16 * j);
  }
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__)) && !defined(MLOD_NO_TARGET_CLONES)
#define MLOD_HIERARCHY_V3 1
// x86-64-v3 (AVX2, FMA): the palette product two columns at a time, model columns
// broadcast to both halves, the inverse bind's elements pre-splatted (m_splat).
__attribute__((target("arch=x86-64-v3"), always_inline)) inline void jointV3(const float* __restrict parent,
                                                                         const float* __restrict local,
                                                                         const float* __restrict s, float* model,
                                                                         float* __restrict palette) {
  mulLane(parent, local, model);
  const __m256 m0 = _mm256_broadcast_ps(reinterpret_cast<const __m128*>(model));
  const __m256 m1 = _mm256_broadcast_ps(reinterpret_cast<const __m128*>(model + 4));
  const __m256 m2 = _mm256_broadcast_ps(reinterpret_cast<const __m128*>(model + 8));
  const __m256 m3 = _mm256_broadcast_ps(reinterpret_cast<const __m128*>(model + 12));
  __m256 c01 = _mm256_mul_ps(m0, _mm256_loadu_ps(s));
  c01 = _mm256_fmadd_ps(m1, _mm256_loadu_ps(s + 8), c01);
  c01 = _mm256_fmadd_ps(m2, _mm256_loadu_ps(s + 16), c01);
  __m256 c23 = _mm256_blend_ps(_mm256_setzero_ps(), m3, 0xf0); // column 3 adds the model's translation
  c23 = _mm256_fmadd_ps(m0, _mm256_loadu_ps(s + 24), c23);
  c23 = _mm256_fmadd_ps(m1, _mm256_loadu_ps(s + 32), c23);
  c23 = _mm256_fmadd_ps(m2, _mm256_loadu_ps(s + 40), c23);
  _mm256_storeu_ps(palette, c01);
  _mm256_storeu_ps(palette + 8, c23);
}
template <bool SingleRoot> __attribute__((target("arch=x86-64-v3"))) void hierarchyV3(const Hierarchy& h) {
  const float* __restrict locals = h.locals;
  const std::int16_t* __restrict parents = h.parents;
  const float* __restrict splat = h.splat;
  float* models = h.models;
  float* __restrict palette = h.palette;
  const int joints = h.joints;
  jointV3(glm::value_ptr(kIdentity), locals, splat, models, palette); // joint 0, a root
  // block by block of kLanes joints: a joint's local matrix is the next lane of its block
  for (int begin = 0; begin < joints; begin += kLanes) {
    const float* block = locals + begin * LodClip::kLocalArrays;
    const int end = std::min(joints, begin + kLanes);
    for (int j = std::max(begin, 1); j < end; ++j) {
      const int p = parents[j];
      const float* parent = SingleRoot || p >= 0 ? models + 16 * p : glm::value_ptr(kIdentity);
      jointV3(parent, block + (j - begin), splat + 48 * j, models + 16 * j, palette + 16 * j);
    }
  }
}
const bool kHasV3 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#endif

// One character's decode (internal/pose_decode.inl): its clip and frame, its pose and its
// per-joint region cursors and spans.
struct DecodeJob {
  const LodClip& clip;
  std::int32_t i0;
  float fraction;
  float* pose;
  std::uint32_t* cursor;
  internal::JointSpan* span;
};

namespace decode_base {
#include "runtime/internal/pose_decode.inl"
} // namespace decode_base

#if defined(MLOD_HIERARCHY_V3) && !defined(__clang__)
#define MLOD_DECODE_V3_BUILT 1
#pragma GCC push_options
#pragma GCC target("arch=x86-64-v3")
namespace decode_v3 {
#define MLOD_DECODE_V3 1
#include "runtime/internal/pose_decode.inl"
#undef MLOD_DECODE_V3
} // namespace decode_v3
#pragma GCC pop_options
#endif

} // namespace

struct PoseEvaluation {
  using State = PoseEvaluatorContext::CharacterState;
  using Scratch = PoseEvaluatorContext::Scratch;

  static void runRange(void* data, int begin, int end, int thread) {
    const PoseEvaluatorJob& job = *static_cast<const PoseEvaluatorJob*>(data);
    Scratch& scratch = job.context->m_scratch[static_cast<std::size_t>(thread)];
    const std::size_t poseFloats = job.context->m_poseFloats;
    for (int c = begin; c < end; ++c) {
      if (c + 1 < end) {
        // the next character's pose on its way to the cache while this one is evaluated
        const float* next = job.context->m_pose.data() + static_cast<std::size_t>(c + 1) * poseFloats;
        for (std::size_t at = 0; at < poseFloats; at += 16)
          __builtin_prefetch(next + at, 1);
      }
      evaluate(job, c, locate(job, c), scratch);
    }
  }

  // Where character c is in its clip: frame position, whole periods before it, i0 and the
  // fraction past it (LodClip::framePosition(), split()).
  struct Where {
    double f = 0.0;
    std::int64_t loop = 0;
    std::int32_t i0 = 0;
    float fraction = 0.0f;
  };
  static Where locate(const PoseEvaluatorJob& job, int c) {
    const LodClip& clip = *job.clips[static_cast<std::size_t>(c)];
    Where where;
    where.f = clip.framePosition(job.times[static_cast<std::size_t>(c)], &where.loop);
    clip.split(where.f, where.i0, where.fraction);
    return where;
  }

  // A character's pose when it starts a clip: every joint's static rotation, scale and
  // translation (the animated channels are decoded over them), no region, no span but for
  // the joints without clusters (entry i0 at every frame).
  static void startClip(const LodClip& clip, float* pose, std::uint32_t* cursor, internal::JointSpan* span) {
    for (int j = 0; j < clip.jointCount(); ++j) {
      float* p = pose + poseOffset(j);
      const glm::quat& q = clip.staticRotation(j);
      const glm::vec3& s = clip.staticScale(j);
      const glm::vec3& t = clip.staticTranslation(j);
      const float values[kPoseArrays] = {q.x, q.y, q.z, q.w, s.x, s.y, s.z, t.x, t.y, t.z};
      for (int a = 0; a < kPoseArrays; ++a)
        p[a * kLanes] = values[a];
      cursor[j] = (clip.flags(j) & LodClip::kRotationAnimated) ? clip.regionBegin(j) : 0;
      span[j] = (clip.flags(j) & LodClip::kEveryFrame) ? internal::JointSpan{0, INT32_MAX, 0}
                                                         : internal::JointSpan{};
    }
  }

  static void evaluate(const PoseEvaluatorJob& job, int c, const Where& where, Scratch& scratch) {
    PoseEvaluatorContext& ctx = *job.context;
    const LodClip& clip = *job.clips[static_cast<std::size_t>(c)];
    State& st = ctx.m_states[static_cast<std::size_t>(c)];
    const double t = job.times[static_cast<std::size_t>(c)];
    const int blendFrames = job.blendFrames;
    const std::size_t at = static_cast<std::size_t>(c) * static_cast<std::size_t>(ctx.m_joints);
    if (st.clip != &clip) {
      if (st.clip && blendFrames > 0 && st.blendFrames == blendFrames)
        startLevelBlend(job, c, t);
      else
        st.levelBlend = false;
      st.clip = &clip;
      startClip(clip, ctx.m_pose.data() + static_cast<std::size_t>(c) * ctx.m_poseFloats, &ctx.m_cursor[at],
                &ctx.m_span[at]);
    }
    st.blendFrames = blendFrames;
    if (clip.scaled())
      poseScaled(job, c, t, where, scratch);
    else if (scratch.singleRoot)
      poseUnscaled(job, c, t, where, scratch);
    else
      poseUnscaledRoots(job, c, t, where, scratch);
  }
  MLOD_RUNTIME_CLONES static void poseScaled(const PoseEvaluatorJob& job, int c, double t, const Where& where,
                                             Scratch& scratch) {
    pose<true, false>(job, c, t, where, scratch);
  }
  MLOD_RUNTIME_CLONES static void poseUnscaled(const PoseEvaluatorJob& job, int c, double t, const Where& where,
                                               Scratch& scratch) {
    pose<false, true>(job, c, t, where, scratch);
  }
  MLOD_RUNTIME_CLONES static void poseUnscaledRoots(const PoseEvaluatorJob& job, int c, double t, const Where& where,
                                                    Scratch& scratch) {
    pose<false, false>(job, c, t, where, scratch);
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

  // Joint j's rotation in `pose` premultiplied by `offset` (unnormalised).
  static void apply(float* pose, int j, const glm::quat& offset) {
    float* s = pose + poseOffset(j);
    const glm::quat r = offset * glm::quat(s[kAw * kLanes], s[kAx * kLanes], s[kAy * kLanes], s[kAz * kLanes]);
    s[kAx * kLanes] = r.x;
    s[kAy * kLanes] = r.y;
    s[kAz * kLanes] = r.z;
    s[kAw * kLanes] = r.w;
  }

  // The wrap's and a level change's offsets (a few frames per period or switch), into a
  // copy of the character's pose (its held keys stay as they are).
  static void blendWrapAndLevel(const PoseEvaluatorJob& job, int c, double t, const Where& where, const LodClip& clip,
                                Scratch& scratch, float* pose) {
    PoseEvaluatorContext& ctx = *job.context;
    State& st = ctx.m_states[static_cast<std::size_t>(c)];
    const int blendFrames = job.blendFrames;
    const double inverseBlendFrames = 1.0 / blendFrames;
    const int joints = clip.jointCount();
    if (clip.looping() && where.loop >= 1 && where.i0 < blendFrames) {
      // the wrap's offsets depend on the clip alone: once per thread and run
      if (scratch.wrapClip != &clip) {
        for (int j = 0; j < joints; ++j)
          scratch.wrapOffsets[static_cast<std::size_t>(j)] = wrapOffset(clip, j);
        scratch.wrapClip = &clip;
      }
      const float weight = 1.0f - static_cast<float>(std::min(where.f * inverseBlendFrames, 1.0));
      for (int j = 0; j < joints; ++j) {
        const glm::quat& wrap = scratch.wrapOffsets[static_cast<std::size_t>(j)];
        if (!isIdentity(wrap))
          apply(pose, j, lerpOffset(wrap, weight));
      }
    }
    if (st.levelBlend) {
      const double w = (t - st.levelStart) / st.levelSeconds;
      if (w >= 0.0 && w < 1.0) {
        const glm::quat* offsets = &ctx.m_levelOffset[static_cast<std::size_t>(c) * static_cast<std::size_t>(joints)];
        for (int j = 0; j < joints; ++j)
          if (!isIdentity(offsets[j]))
            apply(pose, j, lerpOffset(offsets[j], static_cast<float>(1.0 - w)));
      } else {
        st.levelBlend = false;
      }
    }
  }

  // SingleRoot: joint 0 is the only joint without a parent.
  template <bool Scaled, bool SingleRoot>
  __attribute__((always_inline)) static inline void pose(const PoseEvaluatorJob& job, int c, double t,
                                                         const Where& where, Scratch& scratch) {
    PoseEvaluatorContext& ctx = *job.context;
    const LodClip& clip = *job.clips[static_cast<std::size_t>(c)];
    const std::int32_t i0 = where.i0;
    const float fraction = where.fraction;
    const int blendFrames = job.blendFrames;
    const int joints = clip.jointCount();
    const std::size_t at = static_cast<std::size_t>(c) * static_cast<std::size_t>(joints);
    float* __restrict pose = ctx.m_pose.data() + static_cast<std::size_t>(c) * ctx.m_poseFloats;
    std::uint32_t* __restrict cursor = &ctx.m_cursor[at];
    internal::JointSpan* __restrict span = &ctx.m_span[at];
    // 1. rotations, translations and scales into the character's pose
    const DecodeJob decode{clip, i0, fraction, pose, cursor, span};
#ifdef MLOD_DECODE_V3_BUILT
    const std::int64_t sampled = kHasV3 ? decode_v3::decodePoseOf(decode) : decode_base::decodePoseOf(decode);
#else
    const std::int64_t sampled = decode_base::decodePoseOf(decode);
#endif

    // 2. the local matrices, 8 joints at once; first, for the few characters whose joints
    //    blend (a wrap, a level change), their offsets into a copy of the pose
    const float* source = pose;
    const int blocks = static_cast<int>(poseBlocks(joints));
    if (blendFrames > 0 && ((clip.looping() && where.loop >= 1 && i0 < blendFrames) ||
                            ctx.m_states[static_cast<std::size_t>(c)].levelBlend)) {
      float* copy = scratch.samples.data();
      std::copy_n(pose, static_cast<std::size_t>(blocks) * kPoseBlock, copy);
      blendWrapAndLevel(job, c, t, where, clip, scratch, copy);
      source = copy;
    }
    float* __restrict locals = scratch.locals.data();
    for (int b = 0; b < blocks; ++b)
      matrixBlock<Scaled>(source + static_cast<std::size_t>(b) * kPoseBlock,
                          locals + static_cast<std::size_t>(b) * kLocalBlock);
    scratch.sampled += sampled;

    // 3. the hierarchy
    const Hierarchy hierarchy{locals,
                              job.parents.data(),
                              glm::value_ptr(job.inverseBinds[0]),
                              ctx.m_splat.data(),
                              glm::value_ptr(job.out_models.empty() ? scratch.models[0] : job.out_models[at]),
                              glm::value_ptr(job.out_palette[at]),
                              joints};
#ifdef MLOD_HIERARCHY_V3
    if (kHasV3) {
      hierarchyV3<SingleRoot>(hierarchy);
      return;
    }
#endif
    hierarchyBase<SingleRoot>(hierarchy);
  }
};

void PoseEvaluatorContext::resize(int characters, int joints, int threads) {
  characters = std::max(characters, 0);
  joints = std::max(joints, 0);
  threads = std::max(threads, 1);
  m_joints = joints;
  m_splat.assign(48 * static_cast<std::size_t>(joints), 0.0f);
  m_inverseBindsSeen = nullptr;
  m_states.assign(static_cast<std::size_t>(characters), CharacterState{});
  m_levelOffset.assign(static_cast<std::size_t>(characters) * static_cast<std::size_t>(joints),
                       glm::quat(1.0f, 0.0f, 0.0f, 0.0f));
  const std::size_t blocks = poseBlocks(joints);
  m_poseFloats = blocks * kPoseBlock;
  m_pose.assign(static_cast<std::size_t>(characters) * m_poseFloats, 0.0f);
  // lanes past the last joint hold the identity (their matrices are computed too, and must
  // not be NaNs)
  for (std::size_t b = 0; b < m_pose.size() / kPoseBlock; ++b)
    for (const int array : {kAw, kSx, kSy, kSz})
      std::fill_n(m_pose.begin() + static_cast<std::ptrdiff_t>(b * kPoseBlock + array * kLanes), kLanes, 1.0f);
  m_cursor.assign(static_cast<std::size_t>(characters) * static_cast<std::size_t>(joints), 0);
  m_span.assign(static_cast<std::size_t>(characters) * static_cast<std::size_t>(joints), internal::JointSpan{});
  m_scratch.clear();
  m_scratch.resize(static_cast<std::size_t>(threads));
  for (Scratch& scratch : m_scratch) {
    scratch.samples.assign(kPoseBlock * blocks, 0.0f);
    scratch.locals.assign(kLocalBlock * blocks, 0.0f);
    scratch.models.assign(std::max<std::size_t>(static_cast<std::size_t>(joints), 1), glm::mat4(1.0f));
    scratch.wrapOffsets.assign(static_cast<std::size_t>(joints), glm::quat(1.0f, 0.0f, 0.0f, 0.0f));
    scratch.wrapClip = nullptr;
  }
}

void PoseEvaluatorContext::reset() {
  for (int c = 0; c < characterCount(); ++c)
    reset(c);
  m_inverseBindsSeen = nullptr;
}

void PoseEvaluatorContext::reset(int character) {
  m_states[static_cast<std::size_t>(character)] = CharacterState{};
}

std::size_t PoseEvaluatorContext::bytesPerCharacter() const {
  return sizeof(CharacterState) + sizeof(glm::quat) * static_cast<std::size_t>(m_joints) +
         m_poseFloats * sizeof(float) + (sizeof(std::uint32_t) + sizeof(internal::JointSpan)) * static_cast<std::size_t>(m_joints);
}

std::size_t PoseEvaluatorContext::byteSize() const {
  std::size_t scratch = 0;
  for (const Scratch& s : m_scratch)
    scratch += sizeof(Scratch) + (s.samples.size() + s.locals.size()) * sizeof(float) +
               s.models.size() * sizeof(glm::mat4);
  return sizeof(*this) + bytesPerCharacter() * m_states.size() + scratch;
}

bool PoseEvaluatorJob::validate(std::string* out_error) const {
  const auto refuse = [out_error](const std::string& why) {
    if (out_error)
      *out_error = why;
    return false;
  };
  if (!context)
    return refuse("no context");
  const std::size_t joints = parents.size();
  if (joints < 1 || joints > 32767)
    return refuse("joint count " + std::to_string(joints) + " is not in [1, 32767]");
  for (std::size_t j = 0; j < joints; ++j)
    if (parents[j] < -1 || parents[j] >= static_cast<std::int32_t>(j))
      return refuse("joint " + std::to_string(j) + "'s parent does not come before it");
  if (inverseBinds.size() != joints)
    return refuse("inverse binds must hold one matrix per joint");
  for (const glm::mat4& m : inverseBinds)
    if (m[0][3] != 0.0f || m[1][3] != 0.0f || m[2][3] != 0.0f || m[3][3] != 1.0f)
      return refuse("an inverse bind is not affine (bottom row 0 0 0 1)");
  const std::size_t characters = clips.size();
  if (times.size() != characters)
    return refuse("clips and times must hold one entry per character");
  if (context->jointCount() != static_cast<int>(joints) ||
      static_cast<std::size_t>(context->characterCount()) < characters)
    return refuse("the context is not sized for " + std::to_string(characters) + " characters of " +
                  std::to_string(joints) + " joints");
  if (context->threadCount() < (pool ? pool->threadCount() : 1))
    return refuse("the context has fewer threads than the pool");
  if (blendFrames < 0 || blendFrames > kMaxBlendFrames)
    return refuse("blend frames " + std::to_string(blendFrames) + " is not in [0, " + std::to_string(kMaxBlendFrames) +
                  "]");
  if (out_palette.size() != characters * joints || (!out_models.empty() && out_models.size() != characters * joints))
    return refuse("outputs must hold characters x joints matrices (models may be empty)");
  for (std::size_t c = 0; c < characters; ++c) {
    const LodClip* clip = clips[c];
    const std::string who = "character " + std::to_string(c);
    if (!clip || clip->jointCount() != static_cast<int>(joints))
      return refuse(who + ": no clip, or a clip of another joint count");
    if (clip->clusterCount() > 0 && clip->blendFrames() != blendFrames)
      return refuse(who + ": its clip was built for " + std::to_string(clip->blendFrames()) +
                    " blend frames (its unfreeze windows are stored), the job asks " + std::to_string(blendFrames));
    const double t = times[c];
    if (!std::isfinite(t) || t < 0.0)
      return refuse(who + ": its time is not finite and >= 0");
    if (!clip->looping() && t * clip->fps() > clip->frameCount() - 1 + 1e-6)
      return refuse(who + ": its time is past the end of a clip that does not loop");
  }
  return true;
}

bool PoseEvaluatorJob::run() const {
  if (!validate())
    return false;
  PoseEvaluatorContext& ctx = *context;
  if (ctx.m_inverseBindsSeen != inverseBinds.data()) {
    // the inverse binds as hierarchyV3() reads them: per joint, [b0[k] x4 | b1[k] x4] and
    // [b2[k] x4 | b3[k] x4] for k = 0, 1, 2 (b_c = column c)
    for (std::size_t j = 0; j < inverseBinds.size(); ++j) {
      float* s = &ctx.m_splat[48 * j];
      const glm::mat4& b = inverseBinds[j];
      for (int pair = 0; pair < 2; ++pair)
        for (int k = 0; k < 3; ++k)
          for (int i = 0; i < 8; ++i)
            s[24 * pair + 8 * k + i] = b[2 * pair + i / 4][k];
    }
    ctx.m_inverseBindsSeen = inverseBinds.data();
  }
  bool singleRoot = true;
  for (std::size_t j = 1; j < parents.size(); ++j)
    singleRoot = singleRoot && parents[j] >= 0;
  for (PoseEvaluatorContext::Scratch& scratch : ctx.m_scratch) {
    scratch.sampled = 0;
    scratch.singleRoot = singleRoot;
    scratch.wrapClip = nullptr; // (a clip may be new at an old address)
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
  for (const PoseEvaluatorContext::Scratch& scratch : ctx.m_scratch)
    ctx.m_lastSampled += scratch.sampled;
  return true;
}

} // namespace mlod
