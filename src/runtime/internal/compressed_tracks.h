#pragma once
// The quantized value streams of a LodClip (docs/architecture.md section 5, "Compressed
// clips"). Runtime-internal: LodClip owns one CompressedStreams; the pose evaluator and
// LodClip's reference path read values with decode() below, one copy of the arithmetic, so
// that what the encoder measured is what every reader shows. Not part of the SDK's surface.
//
// A stream is a list of entries, each a rotation (a unit quaternion) or a vector (a
// translation or scale). LodClip decides what the entries are: for a joint's rotation, one
// key per cluster and the frames outside clusters, in frame order; for a translation or a
// scale, every frame. Entries are cut into chunks of kChunkEntries. Per chunk:
// - the bit width b of its values: 0 (every entry is the chunk's low corner), 1 to kMaxBits
//   (three b-bit values per entry, packed low bit first), or kRawBits (three floats);
// - for a rotation, the component it drops (`drop`): the one farthest from 0 throughout
//   the chunk; every entry is stored with that component positive, and it is rebuilt as
//   sqrt(1 - |others|^2). So w never has to be rebuilt where it is near 0 (a root turning
//   about 180 degrees);
// - per stored value (slot 0, 1, 2: a rotation's components but the dropped one, in order;
//   a vector's x, y, z), its range within the stream's range of that slot, as an 8-bit
//   start and extent in 255ths (range reduction; ACL does the same per segment).
// The encoder picks per chunk the fewest bits whose decoded entries stay within the
// stream's tolerance of the source: an angle for rotations, a distance for vectors.

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <vector>

namespace mlod::internal {

struct LodClipStorage;

inline constexpr int kChunkEntries = 16;
// Three values of at most 19 bits and the offset of the first in its byte (< 8) fit in one
// 64-bit read.
inline constexpr int kMaxBits = 19;
inline constexpr int kRawBits = 32;

struct Chunk {
  std::uint32_t bitOffset = 0; // of its first entry in the streams' bits (a byte boundary when raw)
  std::uint8_t bits = 0;
  std::uint8_t drop = 3;       // a rotation's dropped component (0..3 = x, y, z, w); 3 for vectors
  std::uint8_t start[3] = {0, 0, 0};
  std::uint8_t extent[3] = {0, 0, 0};
};
static_assert(sizeof(Chunk) == 12);

struct Stream {
  // per slot (and a fourth, always 0): the stream's low end and 1/255 of its extent
  float min[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  float unit[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  std::uint32_t chunkBegin = 0;
  std::uint32_t entries = 0;
  bool rotation = false;
};

// The components a rotation chunk stores, by the one it drops.
inline constexpr std::uint8_t kKept[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};

// 1 / (2^b - 1) for b in [0, kMaxBits] (index b; 0 for 0).
inline constexpr float inverseTop(int b) { return b > 0 ? 1.0f / static_cast<float>((1u << b) - 1u) : 0.0f; }
inline constexpr float kInverseTop[kMaxBits + 1] = {
    inverseTop(0),  inverseTop(1),  inverseTop(2),  inverseTop(3),  inverseTop(4),  inverseTop(5),  inverseTop(6),
    inverseTop(7),  inverseTop(8),  inverseTop(9),  inverseTop(10), inverseTop(11), inverseTop(12), inverseTop(13),
    inverseTop(14), inverseTop(15), inverseTop(16), inverseTop(17), inverseTop(18), inverseTop(19)};

// Entry e of a stream, decoded: a rotation as (x, y, z, w) of a unit quaternion (its dropped
// component >= 0), a vector as (x, y, z, 0). `bits` ends with 8 spare bytes.
inline glm::vec4 decode(const Stream& stream, const Chunk* chunks, const std::uint8_t* bits, std::uint32_t e) {
  const Chunk& chunk = chunks[stream.chunkBegin + e / kChunkEntries];
  const std::uint32_t k = e % kChunkEntries;
  const int b = chunk.bits;
  const std::uint8_t* kept = kKept[chunk.drop];
  float v[3];
  if (b == kRawBits) {
    std::memcpy(v, bits + chunk.bitOffset / 8 + 12 * k, sizeof v);
  } else {
    const std::uint64_t at = chunk.bitOffset + 3u * static_cast<std::uint64_t>(b) * k;
    std::uint64_t word;
    std::memcpy(&word, bits + at / 8, sizeof word);
    word >>= at % 8;
    const std::uint64_t mask = (std::uint64_t{1} << b) - 1;
    const float top = kInverseTop[b];
    for (int i = 0; i < 3; ++i) {
      const float unit = stream.unit[i];
      const float q = static_cast<float>(static_cast<std::int32_t>((word >> (b * i)) & mask));
      const float low = stream.min[i] + unit * static_cast<float>(chunk.start[i]);
      const float step = unit * static_cast<float>(chunk.extent[i]) * top;
      v[i] = low + step * q;
    }
  }
  float out[4] = {v[0], v[1], v[2], 0.0f};
  if (stream.rotation) {
    const float rest = 1.0f - (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    out[kept[0]] = v[0];
    out[kept[1]] = v[1];
    out[kept[2]] = v[2];
    out[chunk.drop] = rest > 0.0f ? std::sqrt(rest) : 0.0f;
  }
  return {out[0], out[1], out[2], out[3]};
}

inline glm::quat toQuat(const glm::vec4& v) { return glm::quat(v.w, v.x, v.y, v.z); }

// The evaluator's decoder: the same arithmetic as decode(), four lanes at a time (GCC
// vector extensions, so that each build of the evaluator vectorises it as its target can).
typedef float F4 __attribute__((vector_size(16)));
typedef std::int32_t I4 __attribute__((vector_size(16)));
typedef std::uint8_t B4 __attribute__((vector_size(4)));

// One chunk, ready to read entries from: per slot its low end and step (lane 3: 0).
struct ChunkView {
  F4 low;
  F4 step;
  std::uint64_t bitOffset;
  int bits;
  int drop;
};
inline ChunkView view(const Stream& stream, const Chunk& chunk) {
  B4 start, extent;
  std::memcpy(&start, chunk.start, sizeof start); // start[0..2] and extent[0]: lane 3 is multiplied by 0
  std::memcpy(&extent, chunk.extent, sizeof extent); // extent[0..2] and the next chunk's first byte
  F4 min, unit;
  std::memcpy(&min, stream.min, sizeof min);
  std::memcpy(&unit, stream.unit, sizeof unit);
  const int b = chunk.bits;
  ChunkView out;
  out.low = min + unit * __builtin_convertvector(start, F4);
  out.step = unit * __builtin_convertvector(extent, F4) * (b <= kMaxBits ? kInverseTop[b] : 0.0f);
  out.bitOffset = chunk.bitOffset;
  out.bits = b;
  out.drop = chunk.drop;
  return out;
}
// Entry k of the chunk, its slots (lane 3: 0).
inline F4 slotValues(const ChunkView& chunk, const std::uint8_t* bits, std::uint32_t k) {
  const int b = chunk.bits;
  if (__builtin_expect(b == kRawBits, 0)) {
    float v[3];
    std::memcpy(v, bits + chunk.bitOffset / 8 + 12 * k, sizeof v);
    return F4{v[0], v[1], v[2], 0.0f};
  }
  const std::uint64_t at = chunk.bitOffset + 3u * static_cast<std::uint64_t>(b) * k;
  std::uint64_t word;
  std::memcpy(&word, bits + at / 8, sizeof word);
  word >>= at % 8;
  const std::uint64_t mask = (std::uint64_t{1} << b) - 1;
  const I4 q = {static_cast<std::int32_t>(word & mask), static_cast<std::int32_t>((word >> b) & mask),
                static_cast<std::int32_t>((word >> (2 * b)) & mask), 0};
  return chunk.low + chunk.step * __builtin_convertvector(q, F4);
}
// A rotation's slots as x, y, z, w (the dropped component rebuilt).
inline F4 rotationOf(F4 v, int drop) {
  const float rest = 1.0f - (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  const std::uint8_t* kept = kKept[drop];
  F4 out;
  out[kept[0]] = v[0];
  out[kept[1]] = v[1];
  out[kept[2]] = v[2];
  out[drop] = rest > 0.0f ? std::sqrt(rest) : 0.0f;
  return out;
}
// Entries e and e + 1 of a stream (a rotation's as x, y, z, w).
template <bool Rotation>
inline void decodeTwo(const Stream& stream, const Chunk* chunks, const std::uint8_t* bits, std::uint32_t e, F4& out_a,
                      F4& out_b) {
  const Chunk* chunk = chunks + stream.chunkBegin + e / kChunkEntries;
  const std::uint32_t k = e % kChunkEntries;
  const ChunkView here = view(stream, *chunk);
  out_a = slotValues(here, bits, k);
  if (Rotation)
    out_a = rotationOf(out_a, here.drop);
  if (k + 1 < kChunkEntries) {
    out_b = slotValues(here, bits, k + 1);
    if (Rotation)
      out_b = rotationOf(out_b, here.drop);
  } else {
    const ChunkView next = view(stream, chunk[1]);
    out_b = slotValues(next, bits, 0);
    if (Rotation)
      out_b = rotationOf(out_b, next.drop);
  }
}
// Entry e of a rotation stream as x, y, z, w.
inline F4 decodeRotation(const Stream& stream, const Chunk* chunks, const std::uint8_t* bits, std::uint32_t e) {
  const ChunkView here = view(stream, chunks[stream.chunkBegin + e / kChunkEntries]);
  return rotationOf(slotValues(here, bits, e % kChunkEntries), here.drop);
}

// The streams of one clip, and their encoder.
class CompressedStreams {
public:
  // Adds a stream of `values` (rotations as unit quaternions in x, y, z, w; vectors in x, y,
  // z) whose decoded entries stay within `tolerance` of them (radians between rotations, or
  // the distance between vectors). Returns its index; out_maxError gets the largest error
  // of its entries as decoded.
  int add(std::span<const glm::vec4> values, bool rotation, double tolerance, double* out_maxError = nullptr);
  // Ends the bits with spare bytes for decode()'s 64-bit reads. Call once, after the last add().
  void finish();
  // Does every entry of stream s decode to the same bits?
  bool constant(int s) const;
  // Removes the stream added last (before finish()).
  void dropLast();

  glm::vec4 value(int stream, std::uint32_t entry) const {
    return decode(m_streams[static_cast<std::size_t>(stream)], m_chunks.data(), m_bits.data(), entry);
  }
  const Stream& stream(int s) const { return m_streams[static_cast<std::size_t>(s)]; }
  const Stream* streamData() const { return m_streams.data(); }
  int streamCount() const { return static_cast<int>(m_streams.size()); }
  const Chunk* chunks() const { return m_chunks.data(); }
  const std::uint8_t* bits() const { return m_bits.data(); }
  // Why the streams could not be read within bounds (empty when fine): each stream's chunks
  // follow the one before's, ceil(entries / kChunkEntries) of them, then one spare chunk of
  // zeros; bit widths 0..kMaxBits or kRawBits; a rotation's dropped component 0..3, a
  // vector's 3; every chunk's bits inside the buffer, which ends with 8 spare bytes; ranges
  // finite, their fourth lane 0.
  std::string storageProblem() const;
  // Bytes held (everything a decoder reads).
  std::size_t byteSize() const {
    return m_streams.size() * sizeof(Stream) + m_chunks.size() * sizeof(Chunk) + m_bits.size();
  }

private:
  friend struct LodClipStorage;
  std::vector<Stream> m_streams;
  std::vector<Chunk> m_chunks;
  std::vector<std::uint8_t> m_bits;
  std::uint64_t m_bitCount = 0;
};

} // namespace mlod::internal
