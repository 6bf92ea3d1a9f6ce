// The pose evaluator's decode of one character (pose_evaluator.cpp includes this file
// twice: once as it is, once under `#pragma GCC target("arch=x86-64-v3")` with
// MLOD_DECODE_V3 defined, so that one loop is built for both instruction sets and picked at
// load time).
//
// Per joint whose rotation animates: while frame i0 stays in the joint's span (the
// character's state, two compares) nothing is looked up:
// - frozen (both frames among one cluster's frozen frames): the pose already holds the
//   key, decoded once when the span began;
// - moving: entries i0 + delta and the next, decoded, sign-aligned and lerped (left
//   unnormalised: the matrix divides by the squared length).
// Past its span, the region that holds i0 (the next one, else a search) gives the next
// span. Unfreeze windows are in the stored frames (LodClip's header): nothing to blend here.
// Then every animated translation and scale, lerped. Returns the joints whose local matrix
// changed this frame (PoseEvaluatorContext::jointsSampled()).
//
// Not a header: no include guard, no includes; it expects the names of pose_evaluator.cpp
// (kLanes, PoseArray, poseOffset(), DecodeJob) and the runtime's headers.

#ifdef MLOD_DECODE_V3
#define MLOD_DECODE_INLINE __attribute__((always_inline)) inline
// Per bit width b: the shifts of a frame's three values in its 64-bit word (0, b, 2b; 64
// clears the fourth lane).
struct alignas(32) Shifts {
  long long s[4];
};
constexpr Shifts shiftsOf(int b) { return {{0, b, 2 * b, 64}}; }
alignas(32) constexpr Shifts kShifts[internal::kMaxBits + 1] = {
    shiftsOf(0),  shiftsOf(1),  shiftsOf(2),  shiftsOf(3),  shiftsOf(4),  shiftsOf(5),  shiftsOf(6),
    shiftsOf(7),  shiftsOf(8),  shiftsOf(9),  shiftsOf(10), shiftsOf(11), shiftsOf(12), shiftsOf(13),
    shiftsOf(14), shiftsOf(15), shiftsOf(16), shiftsOf(17), shiftsOf(18), shiftsOf(19)};

using Value = __m128;

// A chunk's low ends and steps per slot (internal::view()).
struct View {
  __m128 low, step;
};
MLOD_DECODE_INLINE View viewOf(const internal::Stream& stream, const internal::Chunk& chunk) {
  // the chunk's 12 bytes and 4 of the next (the streams end with a spare chunk)
  const __m128i d = _mm_loadu_si128(reinterpret_cast<const __m128i*>(&chunk));
  const __m128 start = _mm_cvtepi32_ps(_mm_cvtepu8_epi32(_mm_srli_si128(d, 6)));
  const __m128 extent = _mm_cvtepi32_ps(_mm_cvtepu8_epi32(_mm_srli_si128(d, 9)));
  const __m128 unit = _mm_loadu_ps(stream.unit); // lane 3 is 0: so are the low end's and the step's
  const int b = chunk.bits;
  View out;
  out.low = _mm_add_ps(_mm_loadu_ps(stream.min), _mm_mul_ps(unit, start));
  out.step = _mm_mul_ps(_mm_mul_ps(unit, extent), _mm_set1_ps(b <= internal::kMaxBits ? internal::kInverseTop[b] : 0.0f));
  return out;
}
MLOD_DECODE_INLINE __m128 slotsOf(const internal::Chunk& chunk, const View& view, const std::uint8_t* bits,
                                  std::uint32_t k) {
  const int b = chunk.bits;
  if (__builtin_expect(b == internal::kRawBits, 0)) {
    float v[3];
    std::memcpy(v, bits + chunk.bitOffset / 8 + 12 * k, sizeof v);
    return _mm_setr_ps(v[0], v[1], v[2], 0.0f);
  }
  const std::uint64_t at = chunk.bitOffset + 3u * static_cast<std::uint64_t>(b) * k;
  std::uint64_t word;
  std::memcpy(&word, bits + at / 8, sizeof word);
  word >>= at % 8;
  __m256i w = _mm256_srlv_epi64(_mm256_set1_epi64x(static_cast<long long>(word)),
                                _mm256_load_si256(reinterpret_cast<const __m256i*>(kShifts[b].s)));
  w = _mm256_and_si256(w, _mm256_set1_epi64x(static_cast<long long>((std::uint64_t{1} << b) - 1)));
  const __m128i q = _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(w, _mm256_setr_epi32(0, 2, 4, 6, 0, 0, 0, 0)));
  return _mm_add_ps(view.low, _mm_mul_ps(view.step, _mm_cvtepi32_ps(q)));
}
alignas(16) constexpr int kPlaceV3[4][4] = {{3, 0, 1, 2}, {0, 3, 1, 2}, {0, 1, 3, 2}, {0, 1, 2, 3}};
MLOD_DECODE_INLINE __m128 rotationOf(__m128 v, int drop) {
  const __m128 rest = _mm_max_ps(_mm_sub_ps(_mm_set1_ps(1.0f), _mm_dp_ps(v, v, 0x7f)), _mm_setzero_ps());
  v = _mm_blend_ps(v, _mm_sqrt_ps(rest), 8);
  return _mm_permutevar_ps(v, _mm_load_si128(reinterpret_cast<const __m128i*>(kPlaceV3[drop])));
}
// Per bit width b: the bit offsets of two consecutive entries' values from the first's
// (0, b, 2b in the low half, 3b, 4b, 5b in the high half; lanes 3 and 7 repeat their
// neighbour and are cleared by the zero step).
struct alignas(32) PairOffsets {
  int o[8];
  int mask[8]; // 2^b - 1
};
constexpr PairOffsets pairOffsetsOf(int b) {
  const int m = static_cast<int>((1u << b) - 1u);
  return {{0, b, 2 * b, 2 * b, 3 * b, 4 * b, 5 * b, 5 * b}, {m, m, m, m, m, m, m, m}};
}
alignas(32) constexpr PairOffsets kPairOffsets[internal::kMaxBits + 1] = {
    pairOffsetsOf(0),  pairOffsetsOf(1),  pairOffsetsOf(2),  pairOffsetsOf(3),  pairOffsetsOf(4),
    pairOffsetsOf(5),  pairOffsetsOf(6),  pairOffsetsOf(7),  pairOffsetsOf(8),  pairOffsetsOf(9),
    pairOffsetsOf(10), pairOffsetsOf(11), pairOffsetsOf(12), pairOffsetsOf(13), pairOffsetsOf(14),
    pairOffsetsOf(15), pairOffsetsOf(16), pairOffsetsOf(17), pairOffsetsOf(18), pairOffsetsOf(19)};
alignas(32) constexpr int kPlacePairV3[4][8] = {
    {3, 0, 1, 2, 3, 0, 1, 2}, {0, 3, 1, 2, 0, 3, 1, 2}, {0, 1, 3, 2, 0, 1, 3, 2}, {0, 1, 2, 3, 0, 1, 2, 3}};
// Entries e and e + 1 of a stream (a rotation's as x, y, z, w). When both lie in one
// packed chunk (15 times in 16), their six values come in one gather of 32-bit words
// (a value and its offset in its first byte span at most 19 + 7 bits) and are rebuilt
// together, one entry per 128-bit half.
template <bool Rotation>
MLOD_DECODE_INLINE void decodePair(const internal::Stream& stream, const internal::Chunk* chunks,
                                  const std::uint8_t* bits, std::uint32_t e, __m128& out_a, __m128& out_b) {
  const internal::Chunk* chunk = chunks + stream.chunkBegin + e / internal::kChunkEntries;
  const std::uint32_t k = e % internal::kChunkEntries;
  const int b = chunk->bits;
  const View here = viewOf(stream, *chunk);
  if (__builtin_expect(k + 1 < internal::kChunkEntries && b != internal::kRawBits, 1)) {
    const __m256i at =
        _mm256_add_epi32(_mm256_set1_epi32(static_cast<int>(chunk->bitOffset + 3u * static_cast<std::uint32_t>(b) * k)),
                         _mm256_load_si256(reinterpret_cast<const __m256i*>(kPairOffsets[b].o)));
    const __m256i words = _mm256_i32gather_epi32(reinterpret_cast<const int*>(bits), _mm256_srli_epi32(at, 3), 1);
    const __m256i q = _mm256_and_si256(_mm256_srlv_epi32(words, _mm256_and_si256(at, _mm256_set1_epi32(7))),
                                       _mm256_load_si256(reinterpret_cast<const __m256i*>(kPairOffsets[b].mask)));
    __m256 v = _mm256_fmadd_ps(_mm256_set_m128(here.step, here.step), _mm256_cvtepi32_ps(q),
                               _mm256_set_m128(here.low, here.low));
    if (Rotation) {
      const __m256 rest = _mm256_max_ps(_mm256_sub_ps(_mm256_set1_ps(1.0f), _mm256_dp_ps(v, v, 0x7f)), _mm256_setzero_ps());
      v = _mm256_blend_ps(v, _mm256_sqrt_ps(rest), 0x88);
      v = _mm256_permutevar_ps(v, _mm256_load_si256(reinterpret_cast<const __m256i*>(kPlacePairV3[chunk->drop])));
    }
    out_a = _mm256_castps256_ps128(v);
    out_b = _mm256_extractf128_ps(v, 1);
    return;
  }
  out_a = slotsOf(*chunk, here, bits, k);
  if (Rotation)
    out_a = rotationOf(out_a, chunk->drop);
  if (k + 1 < internal::kChunkEntries) {
    out_b = slotsOf(*chunk, here, bits, k + 1);
    if (Rotation)
      out_b = rotationOf(out_b, chunk->drop);
  } else {
    const View next = viewOf(stream, chunk[1]);
    out_b = slotsOf(chunk[1], next, bits, 0);
    if (Rotation)
      out_b = rotationOf(out_b, chunk[1].drop);
  }
}
MLOD_DECODE_INLINE __m128 decodeKey(const internal::Stream& stream, const internal::Chunk* chunks,
                                    const std::uint8_t* bits, std::uint32_t e) {
  const internal::Chunk& chunk = chunks[stream.chunkBegin + e / internal::kChunkEntries];
  return rotationOf(slotsOf(chunk, viewOf(stream, chunk), bits, e % internal::kChunkEntries), chunk.drop);
}
// a + (b - a) * fraction, b taken the shorter way
MLOD_DECODE_INLINE __m128 lerpShorter(__m128 a, __m128 b, float fraction) {
  const __m128 sign = _mm_and_ps(_mm_dp_ps(a, b, 0xff), _mm_set1_ps(-0.0f));
  b = _mm_xor_ps(b, sign);
  return _mm_add_ps(a, _mm_mul_ps(_mm_sub_ps(b, a), _mm_set1_ps(fraction)));
}
MLOD_DECODE_INLINE __m128 lerp(__m128 a, __m128 b, float fraction) {
  return _mm_add_ps(a, _mm_mul_ps(_mm_sub_ps(b, a), _mm_set1_ps(fraction)));
}
// Four lanes (or three) into the pose's arrays `first`, first + 1, ... of joint lane p.
MLOD_DECODE_INLINE void put4(float* p, __m128 v) {
  _mm_store_ss(p, v);
  p[kLanes] = _mm_cvtss_f32(_mm_shuffle_ps(v, v, 1));
  p[2 * kLanes] = _mm_cvtss_f32(_mm_shuffle_ps(v, v, 2));
  p[3 * kLanes] = _mm_cvtss_f32(_mm_shuffle_ps(v, v, 3));
}
MLOD_DECODE_INLINE void put3(float* p, __m128 v) {
  _mm_store_ss(p, v);
  p[kLanes] = _mm_cvtss_f32(_mm_shuffle_ps(v, v, 1));
  p[2 * kLanes] = _mm_cvtss_f32(_mm_shuffle_ps(v, v, 2));
}
#else
#define MLOD_DECODE_INLINE inline
using Value = internal::F4;
template <bool Rotation>
MLOD_DECODE_INLINE void decodePair(const internal::Stream& stream, const internal::Chunk* chunks,
                                  const std::uint8_t* bits, std::uint32_t e, Value& out_a, Value& out_b) {
  internal::decodeTwo<Rotation>(stream, chunks, bits, e, out_a, out_b);
}
MLOD_DECODE_INLINE Value decodeKey(const internal::Stream& stream, const internal::Chunk* chunks,
                                   const std::uint8_t* bits, std::uint32_t e) {
  return internal::decodeRotation(stream, chunks, bits, e);
}
MLOD_DECODE_INLINE Value lerpShorter(Value a, Value b, float fraction) {
  const Value ab = a * b;
  if (ab[0] + ab[1] + ab[2] + ab[3] < 0.0f)
    b = -b;
  return a + (b - a) * fraction;
}
MLOD_DECODE_INLINE Value lerp(Value a, Value b, float fraction) { return a + (b - a) * fraction; }
MLOD_DECODE_INLINE void put4(float* p, Value v) {
  for (int i = 0; i < 4; ++i)
    p[i * kLanes] = v[i];
}
MLOD_DECODE_INLINE void put3(float* p, Value v) {
  for (int i = 0; i < 3; ++i)
    p[i * kLanes] = v[i];
}
#endif

template <class Regions> std::int64_t decodePose(const DecodeJob& job) {
  const LodClip& clip = job.clip;
  const std::int32_t i0 = job.i0;
  const float fraction = job.fraction;
  float* __restrict pose = job.pose;
  std::uint32_t* __restrict cursor = job.cursor;
  internal::JointSpan* __restrict span = job.span;
  const internal::CompressedStreams& streams = clip.streams();
  const internal::Chunk* chunks = streams.chunks();
  const std::uint8_t* bits = streams.bits();
  const Regions regions{clip.regionWords()};
  const std::uint8_t* flags = clip.jointFlags();
  const std::int16_t* rotationJoints = clip.rotationJoints().data();
  const std::size_t rotationCount = clip.rotationJoints().size();
  const internal::Stream* rotationStreams = streams.streamData(); // stream i: rotation joint i's
  std::int64_t sampled = 0;
  for (std::size_t i = 0; i < rotationCount; ++i) {
    const int j = rotationJoints[i];
    float* p = pose + poseOffset(j) + kAx * kLanes;
    const internal::Stream& stream = rotationStreams[i];
    internal::JointSpan& s = span[j];
    if (i0 < s.from || i0 >= s.until) {
      // past its span: the region that holds i0, one of the next few (a character plays
      // forward, a frame or two a run), else a search
      std::uint32_t r = cursor[j];
      if (i0 < regions.first(r) || i0 >= regions.first(r + 1)) {
        const std::uint32_t end = clip.regionBegin(j + 1) - 1; // the sentinel
        std::uint32_t ahead = r + 1;
        if (i0 >= regions.first(r))
          while (ahead < end && ahead < r + 5 && i0 >= regions.first(ahead + 1))
            ++ahead;
        r = i0 >= regions.first(r) && ahead < end && i0 < regions.first(ahead + 1) ? ahead : clip.regionOf(j, i0);
        cursor[j] = r;
      }
      const std::int32_t last = regions.first(r + 1) - static_cast<std::int32_t>(regions.entry(r + 1)) +
                                static_cast<std::int32_t>(regions.entry(r)); // LodClip::lastOf()
      if (i0 < last) {
        // frozen until the cluster's last frame
        put4(p, decodeKey(stream, chunks, bits, regions.entry(r)));
        s = {i0, last, internal::JointSpan::kHeldKey};
        continue;
      }
      // frames i0 and i0 + 1 are consecutive entries up to the region's end
      s = {i0, regions.first(r + 1), static_cast<std::int32_t>(regions.entry(r)) - last};
    } else if (s.delta == internal::JointSpan::kHeldKey) {
      continue; // frozen: the pose holds the key
    }
    Value a, b;
    decodePair<true>(stream, chunks, bits, static_cast<std::uint32_t>(i0 + s.delta), a, b);
    put4(p, lerpShorter(a, b, fraction));
    ++sampled;
  }
  for (const std::int16_t joint : clip.vectorJoints()) {
    const int j = joint;
    float* p = pose + poseOffset(j);
    // its local matrix changes: counted here unless its rotation was decoded above
    sampled += (flags[j] & LodClip::kRotationAnimated) && span[j].delta != internal::JointSpan::kHeldKey ? 0 : 1;
    Value a, b;
    if (const int translation = clip.translationStream(j); translation >= 0) {
      decodePair<false>(streams.stream(translation), chunks, bits, static_cast<std::uint32_t>(i0), a, b);
      put3(p + kPx * kLanes, lerp(a, b, fraction));
    }
    if (const int scale = clip.scaleStream(j); scale >= 0) {
      decodePair<false>(streams.stream(scale), chunks, bits, static_cast<std::uint32_t>(i0), a, b);
      put3(p + kSx * kLanes, lerp(a, b, fraction));
    }
  }
  return sampled;
}

std::int64_t decodePoseOf(const DecodeJob& job) {
  return job.clip.narrowRegions() ? decodePose<LodClip::NarrowRegions>(job) : decodePose<LodClip::WideRegions>(job);
}

#undef MLOD_DECODE_INLINE
