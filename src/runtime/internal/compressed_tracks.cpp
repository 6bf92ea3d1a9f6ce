#include "runtime/internal/compressed_tracks.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

namespace mlod::internal {

namespace {

const Chunk kZeroChunk{};

double errorOf(const glm::vec4& decoded, const glm::vec4& source, bool rotation) {
  if (!rotation)
    return glm::length(glm::dvec3(decoded) - glm::dvec3(source));
  const glm::dvec4 a(decoded), b(source);
  const double norms = glm::length(a) * glm::length(b);
  if (norms <= 0.0)
    return 3.14159265358979;
  const double cosine = std::min(1.0, std::abs(glm::dot(a, b)) / norms);
  return 2.0 * std::acos(cosine);
}

// Appends `count` low bits of `value` to a bit buffer (low bit first).
void putBits(std::vector<std::uint8_t>& bytes, std::uint64_t& bitCount, std::uint64_t value, int count) {
  for (int i = 0; i < count; ++i) {
    const std::uint64_t at = bitCount + static_cast<std::uint64_t>(i);
    if (at / 8 >= bytes.size())
      bytes.push_back(0);
    if ((value >> i) & 1u)
      bytes[at / 8] = static_cast<std::uint8_t>(bytes[at / 8] | (1u << (at % 8)));
  }
  bitCount += static_cast<std::uint64_t>(count);
}

} // namespace

int CompressedStreams::add(std::span<const glm::vec4> values, bool rotation, double tolerance, double* out_maxError) {
  Stream stream;
  stream.rotation = rotation;
  stream.entries = static_cast<std::uint32_t>(values.size());
  stream.chunkBegin = static_cast<std::uint32_t>(m_chunks.size());
  const std::size_t chunkCount = (values.size() + kChunkEntries - 1) / kChunkEntries;

  // what each chunk stores: a rotation's entries with the dropped component made positive
  std::vector<glm::vec4> stored(values.begin(), values.end());
  std::vector<std::uint8_t> drops(chunkCount, 3);
  for (std::size_t c = 0; c < chunkCount; ++c) {
    const std::size_t begin = c * kChunkEntries, end = std::min(values.size(), begin + kChunkEntries);
    if (!rotation)
      continue;
    float best = -1.0f;
    for (std::uint8_t d = 0; d < 4; ++d) {
      float low = std::numeric_limits<float>::max();
      for (std::size_t e = begin; e < end; ++e)
        low = std::min(low, std::abs(values[e][d]));
      if (low > best) {
        best = low;
        drops[c] = d;
      }
    }
    for (std::size_t e = begin; e < end; ++e)
      if (stored[e][drops[c]] < 0.0f)
        stored[e] = -stored[e];
  }
  // each entry's values in slot order, and the stream's range of each slot
  for (std::size_t c = 0; c < chunkCount; ++c)
    for (std::size_t e = c * kChunkEntries; e < std::min(values.size(), (c + 1) * kChunkEntries); ++e) {
      const glm::vec4 v = stored[e];
      stored[e] = glm::vec4(v[kKept[drops[c]][0]], v[kKept[drops[c]][1]], v[kKept[drops[c]][2]], 0.0f);
    }
  float low[4], high[4];
  std::fill_n(low, 4, std::numeric_limits<float>::max());
  std::fill_n(high, 4, std::numeric_limits<float>::lowest());
  for (const glm::vec4& v : stored)
    for (int k = 0; k < 3; ++k) {
      low[k] = std::min(low[k], v[k]);
      high[k] = std::max(high[k], v[k]);
    }
  for (int k = 0; k < 4; ++k) {
    if (low[k] > high[k])
      low[k] = high[k] = 0.0f;
    stream.min[k] = low[k];
    stream.unit[k] = (high[k] - low[k]) / 255.0f;
  }
  m_streams.push_back(stream);
  const int index = static_cast<int>(m_streams.size()) - 1;

  double maxError = 0.0;
  std::vector<std::uint8_t> trial;
  for (std::size_t c = 0; c < chunkCount; ++c) {
    const std::size_t begin = c * kChunkEntries, end = std::min(values.size(), begin + kChunkEntries);
    Chunk chunk;
    chunk.drop = drops[c];
    for (int i = 0; i < 3; ++i) {
      const int k = i;
      const float unit = stream.unit[k];
      if (unit <= 0.0f)
        continue;
      float cLow = std::numeric_limits<float>::max(), cHigh = std::numeric_limits<float>::lowest();
      for (std::size_t e = begin; e < end; ++e) {
        cLow = std::min(cLow, stored[e][k]);
        cHigh = std::max(cHigh, stored[e][k]);
      }
      int s = std::clamp(static_cast<int>(std::floor((cLow - stream.min[k]) / unit)), 0, 255);
      while (s > 0 && stream.min[k] + unit * static_cast<float>(s) > cLow)
        --s;
      int t = std::clamp(static_cast<int>(std::ceil((cHigh - stream.min[k]) / unit)), s, 255);
      while (t < 255 && stream.min[k] + unit * static_cast<float>(t) < cHigh)
        ++t;
      chunk.start[i] = static_cast<std::uint8_t>(s);
      chunk.extent[i] = static_cast<std::uint8_t>(t - s);
    }
    // the fewest bits that hold the tolerance, measured on the decoded entries
    const auto encodeWith = [&](int b, std::vector<std::uint8_t>& out) {
      out.clear();
      std::uint64_t count = 0;
      for (std::size_t e = begin; e < end; ++e) {
        if (b == kRawBits) {
          for (int i = 0; i < 3; ++i) {
            const float v = stored[e][i];
            std::uint32_t word;
            std::memcpy(&word, &v, sizeof word);
            putBits(out, count, word, 32);
          }
          continue;
        }
        for (int i = 0; i < 3; ++i) {
          const int k = i;
          const float unit = stream.unit[k];
          const float base = stream.min[k] + unit * static_cast<float>(chunk.start[i]);
          const float step = unit * static_cast<float>(chunk.extent[i]) * kInverseTop[b];
          const std::uint64_t top = b > 0 ? (std::uint64_t{1} << b) - 1 : 0;
          std::uint64_t q = 0;
          if (step > 0.0f) {
            const double r = std::round((double(stored[e][k]) - double(base)) / double(step));
            q = static_cast<std::uint64_t>(std::clamp(r, 0.0, double(top)));
          }
          putBits(out, count, q, b);
        }
      }
      for (int i = 0; i < 8; ++i)
        out.push_back(0);
    };
    const auto measure = [&](int b, const std::vector<std::uint8_t>& bitsOf) {
      Stream probe = stream;
      probe.chunkBegin = 0;
      Chunk one = chunk;
      one.bits = static_cast<std::uint8_t>(b);
      one.bitOffset = 0;
      double worst = 0.0;
      for (std::size_t e = begin; e < end; ++e) {
        const glm::vec4 decoded = decode(probe, &one, bitsOf.data(), static_cast<std::uint32_t>(e - begin));
        worst = std::max(worst, errorOf(decoded, values[e], rotation));
      }
      return worst;
    };
    int chosen = kRawBits;
    double chosenError = 0.0;
    for (int b = 0; b <= kMaxBits; ++b) {
      encodeWith(b, trial);
      const double worst = measure(b, trial);
      if (worst <= tolerance) {
        chosen = b;
        chosenError = worst;
        break;
      }
    }
    if (chosen == kRawBits) {
      encodeWith(kRawBits, trial);
      chosenError = measure(kRawBits, trial);
      m_bitCount = (m_bitCount + 7) / 8 * 8;
    }
    // `trial` holds the chosen width's bits (the search stopped on it, or raw encoded them)
    chunk.bits = static_cast<std::uint8_t>(chosen);
    chunk.bitOffset = static_cast<std::uint32_t>(m_bitCount);
    const std::uint64_t payload = chosen == kRawBits ? 96u * (end - begin) : 3u * static_cast<std::uint64_t>(chosen) * (end - begin);
    m_bits.resize((m_bitCount + payload + 7) / 8 + 8, 0); // 8 spare bytes: decode() reads 64 bits at a time
    for (std::uint64_t i = 0; i < payload; ++i)
      if ((trial[i / 8] >> (i % 8)) & 1u) {
        const std::uint64_t at = m_bitCount + i;
        m_bits[at / 8] = static_cast<std::uint8_t>(m_bits[at / 8] | (1u << (at % 8)));
      }
    m_bitCount += payload;
    m_chunks.push_back(chunk);
    maxError = std::max(maxError, chosenError);
  }
  if (out_maxError)
    *out_maxError = maxError;
  return index;
}

bool CompressedStreams::constant(int s) const {
  const Stream& stream = m_streams[static_cast<std::size_t>(s)];
  const glm::vec4 first = value(s, 0);
  for (std::uint32_t e = 1; e < stream.entries; ++e) {
    const glm::vec4 v = value(s, e);
    if (std::memcmp(&v, &first, sizeof v) != 0)
      return false;
  }
  return true;
}

void CompressedStreams::dropLast() {
  const Stream& stream = m_streams.back();
  if (stream.chunkBegin < m_chunks.size()) {
    m_bitCount = m_chunks[stream.chunkBegin].bitOffset;
    m_chunks.resize(stream.chunkBegin);
  }
  // the bits the stream wrote past the new end, in the byte they share with the one before
  m_bits.resize((m_bitCount + 7) / 8);
  if (m_bitCount % 8 != 0)
    m_bits.back() = static_cast<std::uint8_t>(m_bits.back() & ((1u << (m_bitCount % 8)) - 1u));
  m_bits.resize(m_bits.size() + 8, 0);
  m_streams.pop_back();
}

std::string CompressedStreams::storageProblem() const {
  // bits addressed as 32-bit offsets (the evaluator's gather), 8 spare bytes at the end
  if (m_bits.size() < 8 || m_bits.size() - 8 > (std::size_t{1} << 29))
    return "a bit buffer of " + std::to_string(m_bits.size()) + " bytes";
  const std::uint64_t bitEnd = 8 * static_cast<std::uint64_t>(m_bits.size() - 8);
  std::uint64_t chunkAt = 0;
  for (std::size_t s = 0; s < m_streams.size(); ++s) {
    const Stream& stream = m_streams[s];
    const std::string what = "stream " + std::to_string(s) + ": ";
    for (int k = 0; k < 4; ++k)
      if (!std::isfinite(stream.min[k]) || !std::isfinite(stream.unit[k]) || stream.unit[k] < 0.0f ||
          (k == 3 && (stream.min[k] != 0.0f || stream.unit[k] != 0.0f)))
        return what + "a range that is not finite, or not 0 in its fourth lane";
    if (stream.entries < 1)
      return what + "no entries";
    const std::uint64_t chunks = (std::uint64_t(stream.entries) + kChunkEntries - 1) / kChunkEntries;
    if (stream.chunkBegin != chunkAt || chunks > m_chunks.size() - std::min<std::uint64_t>(m_chunks.size(), chunkAt))
      return what + "its chunks do not follow the stream before's";
    for (std::uint64_t c = 0; c < chunks; ++c) {
      const Chunk& chunk = m_chunks[static_cast<std::size_t>(chunkAt + c)];
      const std::uint64_t entries = std::min<std::uint64_t>(kChunkEntries, stream.entries - c * kChunkEntries);
      const std::string where = what + "chunk " + std::to_string(c) + ": ";
      if (chunk.bits > kMaxBits && chunk.bits != kRawBits)
        return where + "a bit width of " + std::to_string(chunk.bits);
      if (chunk.drop > 3 || (!stream.rotation && chunk.drop != 3))
        return where + "dropped component " + std::to_string(chunk.drop);
      const bool raw = chunk.bits == kRawBits;
      if (raw && chunk.bitOffset % 8 != 0)
        return where + "raw values off a byte boundary";
      const std::uint64_t payload = raw ? 96 * entries : 3 * std::uint64_t(chunk.bits) * entries;
      if (std::uint64_t(chunk.bitOffset) + payload > bitEnd)
        return where + "its bits lie past the buffer";
    }
    chunkAt += chunks;
  }
  // and the spare chunk that the decoders read past a stream's last (finish())
  if (m_chunks.size() != chunkAt + 1)
    return std::to_string(m_chunks.size()) + " chunks where the streams hold " + std::to_string(chunkAt) + " and a spare";
  if (std::memcmp(&m_chunks.back(), &kZeroChunk, sizeof(Chunk)) != 0)
    return "a spare chunk that is not the empty one";
  for (std::size_t i = m_bits.size() - 8; i < m_bits.size(); ++i)
    if (m_bits[i] != 0)
      return "spare bytes that are not zeros";
  return {};
}

void CompressedStreams::finish() {
  m_bits.resize((m_bitCount + 7) / 8 + 8, 0);
  std::fill(m_bits.begin() + static_cast<std::ptrdiff_t>((m_bitCount + 7) / 8), m_bits.end(), std::uint8_t{0});
  // a spare chunk: decodePair() reads a chunk's 12 bytes as four 4-byte groups
  m_chunks.push_back(Chunk{});
  m_bits.shrink_to_fit();
  m_chunks.shrink_to_fit();
  m_streams.shrink_to_fit();
}

} // namespace mlod::internal
