#include "runtime/bundle.h"

#include "runtime/input_file.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>

namespace mlod {

std::string bundlePlanProblem(std::uint64_t frames, int joints, int levels, bool withOriginal) {
  if (joints < 1)
    return "has no skeleton: a runtime bundle holds a skeleton and its clips (a mesh alone exports to glTF)";
  const std::uint64_t perFrame = (withOriginal ? std::uint64_t(joints) : 0) +
                                 std::uint64_t(std::max(levels - (withOriginal ? 1 : 0), 0));
  const std::uint64_t least = frames * perFrame;
  if (least <= kMaxBundleJointFrames)
    return {};
  return "a runtime bundle holds at most " + std::to_string(kMaxBundleJointFrames) + " joint-frames; these " +
         std::to_string(levels) + " levels of " + std::to_string(frames) + " frames (" + std::to_string(joints) +
         " joints at the original level) need at least " + std::to_string(least) +
         ": export fewer levels (without level 0) or a shorter clip";
}

namespace {

// Section types (docs/bundle-format.md).
constexpr std::uint32_t kSectionMeta = 1;
constexpr std::uint32_t kSectionLevel = 2;
constexpr std::size_t kHeaderBytes = 24;       // magic, version, section count, file size
constexpr std::size_t kSectionEntryBytes = 24; // type, crc, offset, size
constexpr std::uint32_t kMaxLevels = 65535;
constexpr std::uint32_t kMaxString = 1u << 20;

// ---- writing ----

class Writer {
public:
  std::vector<std::uint8_t> bytes;
  void u8(std::uint8_t v) { bytes.push_back(v); }
  void u16(std::uint16_t v) {
    for (int i = 0; i < 2; ++i)
      bytes.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void u32(std::uint32_t v) {
    for (int i = 0; i < 4; ++i)
      bytes.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void u64(std::uint64_t v) {
    for (int i = 0; i < 8; ++i)
      bytes.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void i32(std::int32_t v) { u32(static_cast<std::uint32_t>(v)); }
  void f32(float v) { u32(std::bit_cast<std::uint32_t>(v)); }
  void f64(double v) { u64(std::bit_cast<std::uint64_t>(v)); }
  void str(const std::string& s) {
    u32(static_cast<std::uint32_t>(s.size()));
    bytes.insert(bytes.end(), s.begin(), s.end());
  }
  void vec3(const glm::vec3& v) {
    f32(v.x);
    f32(v.y);
    f32(v.z);
  }
  void quat(const glm::quat& q) {
    f32(q.x);
    f32(q.y);
    f32(q.z);
    f32(q.w);
  }
  void mat4(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r)
        f32(m[c][r]);
  }
};

} // namespace

// A clip's storage in a level section (docs/bundle-format.md, "Clip"): LodClip's members as
// they lie in memory but for what follows from them (the joint lists, the scaled flag, the
// region width, the streams' spare chunk and spare bytes), which the reader derives;
// readBundle() then checks the whole against LodClip::storageProblem() (validateBundle()).
struct internal::LodClipStorage {
  template <class W> static void write(W& w, const std::string& name, const LodClip& clip) {
    w.str(name);
    w.f64(clip.m_fps);
    w.i32(clip.m_frameCount);
    w.u8(clip.m_looping ? 1 : 0);
    w.i32(clip.m_blendFrames);
    w.f64(clip.m_precisionCm);
    w.f64(clip.m_encodedErrorCm);
    w.i32(clip.m_clusterCount);
    for (std::size_t j = 0; j < clip.m_flags.size(); ++j) {
      w.u8(clip.m_flags[j]);
      w.quat(clip.m_staticRotation[j]);
      w.vec3(clip.m_staticTranslation[j]);
      w.vec3(clip.m_staticScale[j]);
      w.i32(clip.m_rotationStream[j]);
      w.i32(clip.m_translationStream[j]);
      w.i32(clip.m_scaleStream[j]);
    }
    for (std::uint32_t begin : clip.m_regionBegin)
      w.u32(begin);
    w.u32(static_cast<std::uint32_t>(clip.m_regionWords.size()));
    for (std::uint32_t word : clip.m_regionWords)
      w.u32(word);
    const CompressedStreams& streams = clip.m_streams;
    w.u32(static_cast<std::uint32_t>(streams.m_streams.size()));
    for (const Stream& stream : streams.m_streams) {
      for (int k = 0; k < 3; ++k)
        w.f32(stream.min[k]);
      for (int k = 0; k < 3; ++k)
        w.f32(stream.unit[k]);
      w.u32(stream.chunkBegin);
      w.u32(stream.entries);
      w.u8(stream.rotation ? 1 : 0);
    }
    w.u32(static_cast<std::uint32_t>(streams.m_chunks.size() - 1)); // not the spare
    for (std::size_t c = 0; c + 1 < streams.m_chunks.size(); ++c) {
      const Chunk& chunk = streams.m_chunks[c];
      w.u32(chunk.bitOffset);
      w.u8(chunk.bits);
      w.u8(chunk.drop);
      for (int k = 0; k < 3; ++k)
        w.u8(chunk.start[k]);
      for (int k = 0; k < 3; ++k)
        w.u8(chunk.extent[k]);
    }
    const std::size_t bytes = streams.m_bits.size() - 8; // not the spare bytes
    w.u32(static_cast<std::uint32_t>(bytes));
    w.bytes.insert(w.bytes.end(), streams.m_bits.begin(), streams.m_bits.begin() + static_cast<std::ptrdiff_t>(bytes));
  }

  // Reads one clip of a level of `joints` joints; false (and the reader's error) when the
  // bytes do not hold a clip the evaluator can read.
  template <class R> static bool read(R& r, int joints, BundleClip& out) {
    out.name = r.str("clip name");
    LodClip& clip = out.clip;
    clip.m_fps = r.f64();
    clip.m_frameCount = r.i32();
    const std::uint8_t looping = r.u8();
    clip.m_blendFrames = r.i32();
    clip.m_precisionCm = r.f64();
    clip.m_encodedErrorCm = r.f64();
    clip.m_clusterCount = r.i32();
    if (!r.ok())
      return false;
    const std::string what = "clip '" + out.name + "': ";
    if (looping > 1)
      return r.fail(what + "a looping flag of " + std::to_string(looping)), false;
    clip.m_looping = looping == 1;
    clip.m_jointCount = joints;
    const std::size_t n = static_cast<std::size_t>(joints);
    if (!r.fits(n, 53, "clip joints"))
      return false;
    clip.m_flags.resize(n);
    clip.m_staticRotation.resize(n);
    clip.m_staticTranslation.resize(n);
    clip.m_staticScale.resize(n);
    clip.m_rotationStream.resize(n);
    clip.m_translationStream.resize(n);
    clip.m_scaleStream.resize(n);
    for (std::size_t j = 0; j < n; ++j) {
      clip.m_flags[j] = r.u8();
      clip.m_staticRotation[j] = r.quat();
      clip.m_staticTranslation[j] = r.vec3();
      clip.m_staticScale[j] = r.vec3();
      clip.m_rotationStream[j] = r.i32();
      clip.m_translationStream[j] = r.i32();
      clip.m_scaleStream[j] = r.i32();
    }
    if (!r.fits(n + 1, 4, "region index"))
      return false;
    clip.m_regionBegin.resize(n + 1);
    for (std::uint32_t& begin : clip.m_regionBegin)
      begin = r.u32();
    const std::uint32_t words = r.u32();
    if (!r.fits(words, 4, "regions"))
      return false;
    clip.m_regionWords.resize(words);
    for (std::uint32_t& word : clip.m_regionWords)
      word = r.u32();
    clip.m_narrowRegions = clip.m_frameCount <= 0xffff;
    CompressedStreams& streams = clip.m_streams;
    const std::uint32_t streamCount = r.u32();
    if (!r.fits(streamCount, 33, "streams"))
      return false;
    streams.m_streams.resize(streamCount);
    for (Stream& stream : streams.m_streams) {
      for (int k = 0; k < 3; ++k)
        stream.min[k] = r.f32();
      for (int k = 0; k < 3; ++k)
        stream.unit[k] = r.f32();
      stream.chunkBegin = r.u32();
      stream.entries = r.u32();
      const std::uint8_t rotation = r.u8();
      if (rotation > 1)
        return r.fail(what + "a stream kind of " + std::to_string(rotation)), false;
      stream.rotation = rotation == 1;
    }
    const std::uint32_t chunkCount = r.u32();
    if (!r.fits(chunkCount, 12, "chunks"))
      return false;
    streams.m_chunks.resize(std::size_t(chunkCount) + 1); // and the spare
    for (std::uint32_t c = 0; c < chunkCount; ++c) {
      Chunk& chunk = streams.m_chunks[c];
      chunk.bitOffset = r.u32();
      chunk.bits = r.u8();
      chunk.drop = r.u8();
      for (int k = 0; k < 3; ++k)
        chunk.start[k] = r.u8();
      for (int k = 0; k < 3; ++k)
        chunk.extent[k] = r.u8();
    }
    const std::uint32_t bytes = r.u32();
    if (!r.fits(bytes, 1, "stream bytes"))
      return false;
    streams.m_bits.resize(std::size_t(bytes) + 8, 0); // and the spare bytes
    r.copy(streams.m_bits.data(), bytes);
    streams.m_bitCount = 8 * std::uint64_t(bytes);
    if (!r.ok())
      return false;
    clip.deriveJointLists();
    return true; // its storage is checked with the rest (validateBundle())
  }
};

namespace {

void writeLevel(Writer& w, const BundleLevel& level) {
  w.i32(level.index);
  w.str(level.name);
  for (double v : {level.motionThreshold, level.meshRatio, level.switchDistanceCm, level.pixelError,
                   level.screenSizePixels, level.motionErrorCm, level.meshErrorCm})
    w.f64(v);
  w.u32(static_cast<std::uint32_t>(level.parents.size()));
  for (std::size_t j = 0; j < level.parents.size(); ++j) {
    w.i32(level.fullJoints[j]);
    w.i32(level.parents[j]);
    w.mat4(level.inverseBinds[j]);
  }
  w.u32(static_cast<std::uint32_t>(level.clips.size()));
  for (const BundleClip& clip : level.clips)
    internal::LodClipStorage::write(w, clip.name, clip.clip);
  w.u8(level.mesh ? 1 : 0);
  if (!level.mesh)
    return;
  const BundleMesh& mesh = *level.mesh;
  w.u32(static_cast<std::uint32_t>(mesh.positions.size()));
  w.u32(static_cast<std::uint32_t>(mesh.indices.size()));
  w.u8(mesh.normals.empty() ? 0 : 1);
  for (const glm::vec3& p : mesh.positions)
    w.vec3(p);
  for (const glm::vec3& n : mesh.normals)
    w.vec3(n);
  for (std::uint32_t i : mesh.indices)
    w.u32(i);
  for (const glm::u16vec4& j : mesh.joints)
    for (int k = 0; k < 4; ++k)
      w.u16(j[k]);
  for (const glm::vec4& x : mesh.weights)
    for (int k = 0; k < 4; ++k)
      w.f32(x[k]);
}

// ---- reading ----

// A bounds-checked cursor over one section; the first failure sticks.
class Reader {
public:
  Reader(std::span<const std::uint8_t> bytes, std::string where) : m_bytes(bytes), m_where(std::move(where)) {}

  bool ok() const { return m_error.empty(); }
  const std::string& error() const { return m_error; }
  std::size_t remaining() const { return m_bytes.size() - m_at; }
  bool atEnd() const { return m_at == m_bytes.size(); }
  void fail(const std::string& message) {
    if (m_error.empty())
      m_error = m_where + ": " + message + " (at byte " + std::to_string(m_at) + ")";
  }
  // `count` items of `itemBytes` each fit in what is left (checked before allocating).
  bool fits(std::uint64_t count, std::uint64_t itemBytes, const char* what) {
    if (!ok())
      return false;
    if (itemBytes != 0 && count > remaining() / itemBytes) {
      fail(std::string(what) + ": " + std::to_string(count) + " items do not fit in the " +
           std::to_string(remaining()) + " bytes left");
      return false;
    }
    return true;
  }

  std::uint64_t raw(int n) {
    if (!ok() || remaining() < std::size_t(n)) {
      fail("truncated");
      m_at = m_bytes.size();
      return 0;
    }
    std::uint64_t v = 0;
    for (int i = 0; i < n; ++i)
      v |= std::uint64_t(m_bytes[m_at + std::size_t(i)]) << (8 * i);
    m_at += std::size_t(n);
    return v;
  }
  void copy(std::uint8_t* out, std::size_t n) {
    if (!ok() || remaining() < n) {
      fail("truncated");
      m_at = m_bytes.size();
      return;
    }
    std::memcpy(out, m_bytes.data() + m_at, n);
    m_at += n;
  }
  std::uint8_t u8() { return static_cast<std::uint8_t>(raw(1)); }
  std::uint16_t u16() { return static_cast<std::uint16_t>(raw(2)); }
  std::uint32_t u32() { return static_cast<std::uint32_t>(raw(4)); }
  std::uint64_t u64() { return raw(8); }
  std::int32_t i32() { return static_cast<std::int32_t>(u32()); }
  float f32() { return std::bit_cast<float>(u32()); }
  double f64() { return std::bit_cast<double>(u64()); }
  std::string str(const char* what) {
    const std::uint32_t n = u32();
    if (n > kMaxString || !fits(n, 1, what))
      return fail(std::string(what) + ": a string of " + std::to_string(n) + " bytes"), std::string();
    std::string s(reinterpret_cast<const char*>(m_bytes.data() + m_at), n);
    m_at += n;
    return s;
  }
  glm::vec3 vec3() {
    const float x = f32(), y = f32(), z = f32();
    return {x, y, z};
  }
  glm::quat quat() {
    const float x = f32(), y = f32(), z = f32(), w = f32();
    return glm::quat(w, x, y, z);
  }
  glm::mat4 mat4() {
    glm::mat4 m(0.0f);
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r)
        m[c][r] = f32();
    return m;
  }

private:
  std::span<const std::uint8_t> m_bytes;
  std::size_t m_at = 0;
  std::string m_where;
  std::string m_error;
};

bool readLevel(Reader& r, BundleLevel& level) {
  level.index = r.i32();
  level.name = r.str("level name");
  for (double* v : {&level.motionThreshold, &level.meshRatio, &level.switchDistanceCm, &level.pixelError,
                    &level.screenSizePixels, &level.motionErrorCm, &level.meshErrorCm})
    *v = r.f64();
  const std::uint32_t joints = r.u32();
  if (!r.fits(joints, 72, "joints"))
    return false;
  if (joints < 1 || joints > 32767)
    return r.fail("a level of " + std::to_string(joints) + " joints"), false;
  for (std::uint32_t j = 0; j < joints; ++j) {
    level.fullJoints.push_back(r.i32());
    const std::int32_t parent = r.i32();
    level.parents.push_back(static_cast<std::int16_t>(parent < -1 || parent > 32767 ? 32767 : parent));
    level.inverseBinds.push_back(r.mat4());
  }
  const std::uint32_t clips = r.u32();
  if (!r.fits(clips, 41 + 53, "clips")) // a clip's fields, and at least one joint's
    return false;
  for (std::uint32_t c = 0; c < clips; ++c) {
    BundleClip& clip = level.clips.emplace_back();
    if (!internal::LodClipStorage::read(r, static_cast<int>(joints), clip))
      return false;
  }
  const std::uint8_t hasMesh = r.u8();
  if (hasMesh > 1)
    return r.fail("a mesh flag of " + std::to_string(hasMesh)), false;
  if (hasMesh == 1) {
    BundleMesh mesh;
    const std::uint32_t vertices = r.u32();
    const std::uint32_t indices = r.u32();
    const std::uint8_t hasNormals = r.u8();
    if (hasNormals > 1)
      return r.fail("a normals flag of " + std::to_string(hasNormals)), false;
    const std::uint64_t perVertex = 12 + (hasNormals ? 12 : 0) + 8 + 16;
    if (!r.fits(vertices, perVertex, "vertices") || !r.fits(std::uint64_t(vertices) * perVertex / 4 + indices, 4, "mesh"))
      return false;
    for (std::uint32_t v = 0; v < vertices; ++v)
      mesh.positions.push_back(r.vec3());
    for (std::uint32_t v = 0; hasNormals && v < vertices; ++v)
      mesh.normals.push_back(r.vec3());
    for (std::uint32_t i = 0; i < indices; ++i)
      mesh.indices.push_back(r.u32());
    for (std::uint32_t v = 0; v < vertices; ++v) {
      glm::u16vec4 j;
      for (int k = 0; k < 4; ++k)
        j[k] = r.u16();
      mesh.joints.push_back(j);
    }
    for (std::uint32_t v = 0; v < vertices; ++v) {
      glm::vec4 x;
      for (int k = 0; k < 4; ++k)
        x[k] = r.f32();
      mesh.weights.push_back(x);
    }
    level.mesh = std::move(mesh);
  }
  if (r.ok() && !r.atEnd())
    r.fail(std::to_string(r.remaining()) + " bytes left over after the level");
  return r.ok();
}

bool finiteMatrix(const glm::mat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r]))
        return false;
  return m[0][3] == 0.0f && m[1][3] == 0.0f && m[2][3] == 0.0f && m[3][3] == 1.0f;
}

std::string parentsProblem(std::span<const std::int16_t> parents) {
  if (parents.empty())
    return "no joint";
  if (parents[0] != -1)
    return "joint 0 is not the root";
  for (std::size_t j = 1; j < parents.size(); ++j)
    if (parents[j] < 0 || std::size_t(parents[j]) >= j)
      return "joint " + std::to_string(j) + " has parent " + std::to_string(parents[j]) + " (parents come first)";
  return {};
}

} // namespace

std::size_t bundleClipBytes(const BundleClip& clip) {
  Writer w;
  internal::LodClipStorage::write(w, clip.name, clip.clip);
  return w.bytes.size();
}

std::uint32_t crc32(std::span<const std::uint8_t> bytes) {
  static const std::array<std::uint32_t, 256> table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k)
        c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  std::uint32_t c = 0xFFFFFFFFu;
  for (std::uint8_t b : bytes)
    c = table[(c ^ b) & 0xFFu] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}

std::string validateBundle(const Bundle& bundle) {
  if (bundle.name.empty())
    return "the bundle has no name";
  if (bundle.levels.empty() || bundle.levels.size() > kMaxLevels)
    return "a bundle holds 1 to 65,535 levels, not " + std::to_string(bundle.levels.size());
  if (bundle.jointNames.size() != bundle.jointParents.size() || bundle.jointNames.size() > 32767)
    return "the skeleton's names and parents differ in number";
  if (!bundle.jointNames.empty())
    if (std::string problem = parentsProblem(bundle.jointParents); !problem.empty())
      return "skeleton: " + problem;
  if (!std::isfinite(bundle.verticalFovDegrees) || !std::isfinite(bundle.viewportHeightPixels) ||
      !std::isfinite(bundle.boundingRadiusCm))
    return "the projection and bounding radius must be finite";
  std::uint64_t jointFrames = 0;
  for (const BundleLevel& level : bundle.levels)
    for (const BundleClip& clip : level.clips)
      jointFrames += std::uint64_t(clip.clip.frameCount()) * std::uint64_t(clip.clip.jointCount());
  if (jointFrames > kMaxBundleJointFrames)
    return "the clips hold " + std::to_string(jointFrames) + " joint-frames, more than a bundle may (" +
           std::to_string(kMaxBundleJointFrames) + ")";
  const BundleClip* firstClip = nullptr;
  for (const BundleLevel& level : bundle.levels)
    if (!firstClip && !level.clips.empty())
      firstClip = &level.clips.front();
  for (const BundleLevel& level : bundle.levels) {
    const std::string what = "level '" + level.name + "': ";
    const std::size_t n = level.parents.size();
    if (level.fullJoints.size() != n || level.inverseBinds.size() != n)
      return what + "joints, full joints and inverse binds differ in number";
    if (std::string problem = parentsProblem(level.parents); !problem.empty())
      return what + problem;
    for (std::size_t j = 0; j < n; ++j) {
      if (!bundle.jointNames.empty() &&
          (level.fullJoints[j] < 0 || std::size_t(level.fullJoints[j]) >= bundle.jointNames.size()))
        return what + "joint " + std::to_string(j) + " names original joint " + std::to_string(level.fullJoints[j]);
      if (!finiteMatrix(level.inverseBinds[j]))
        return what + "joint " + std::to_string(j) + " has an inverse bind that is not finite and affine";
    }
    for (const BundleClip& clip : level.clips) {
      if (clip.clip.jointCount() != std::int32_t(n))
        return what + "clip '" + clip.name + "' does not match the level's " + std::to_string(n) + " joints";
      if (std::string problem = clip.clip.storageProblem(); !problem.empty()) // e.g. a LodClip never built
        return what + "clip '" + clip.name + "': " + problem;
      if (clip.clip.blendFrames() != firstClip->clip.blendFrames())
        return what + "clip '" + clip.name + "' is built for " + std::to_string(clip.clip.blendFrames()) +
               " blend frames, clip '" + firstClip->name + "' for " + std::to_string(firstClip->clip.blendFrames()) +
               ": a bundle's clips play with one";
    }
    if (level.mesh) {
      const BundleMesh& mesh = *level.mesh;
      const std::size_t v = mesh.positions.size();
      if ((!mesh.normals.empty() && mesh.normals.size() != v) || mesh.joints.size() != v || mesh.weights.size() != v)
        return what + "the mesh's arrays differ in length";
      if (mesh.indices.size() % 3 != 0)
        return what + "the mesh's index count is not a multiple of 3";
      for (std::uint32_t i : mesh.indices)
        if (i >= v)
          return what + "the mesh has index " + std::to_string(i) + " of " + std::to_string(v) + " vertices";
      for (const glm::u16vec4& j : mesh.joints)
        for (int k = 0; k < 4; ++k)
          if (j[k] >= n)
            return what + "the mesh names joint " + std::to_string(j[k]) + " of " + std::to_string(n);
    }
  }
  return {};
}

std::vector<std::uint8_t> writeBundle(const Bundle& bundle, std::string* out_error) {
  if (std::string problem = validateBundle(bundle); !problem.empty()) {
    if (out_error)
      *out_error = problem;
    return {};
  }
  std::vector<std::vector<std::uint8_t>> sections;
  std::vector<std::uint32_t> types;
  {
    Writer w;
    w.str(bundle.name);
    w.str(bundle.source);
    w.f64(bundle.verticalFovDegrees);
    w.f64(bundle.viewportHeightPixels);
    w.f64(bundle.boundingRadiusCm);
    w.u32(static_cast<std::uint32_t>(bundle.levels.size()));
    w.u32(static_cast<std::uint32_t>(bundle.jointNames.size()));
    for (std::size_t j = 0; j < bundle.jointNames.size(); ++j) {
      w.str(bundle.jointNames[j]);
      w.i32(bundle.jointParents[j]);
    }
    sections.push_back(std::move(w.bytes));
    types.push_back(kSectionMeta);
  }
  for (const BundleLevel& level : bundle.levels) {
    Writer w;
    writeLevel(w, level);
    sections.push_back(std::move(w.bytes));
    types.push_back(kSectionLevel);
  }
  const std::size_t tableEnd = kHeaderBytes + sections.size() * kSectionEntryBytes + 4;
  std::size_t total = tableEnd;
  for (const auto& s : sections)
    total += s.size();
  Writer out;
  out.bytes.reserve(total);
  out.bytes.insert(out.bytes.end(), std::begin(kBundleMagic), std::end(kBundleMagic));
  out.u32(kBundleVersion);
  out.u32(static_cast<std::uint32_t>(sections.size()));
  out.u64(total);
  std::size_t offset = tableEnd;
  for (std::size_t i = 0; i < sections.size(); ++i) {
    out.u32(types[i]);
    out.u32(crc32(sections[i]));
    out.u64(offset);
    out.u64(sections[i].size());
    offset += sections[i].size();
  }
  out.u32(crc32(out.bytes)); // header and section table
  for (const auto& s : sections)
    out.bytes.insert(out.bytes.end(), s.begin(), s.end());
  return std::move(out.bytes);
}

std::optional<Bundle> readBundle(std::span<const std::uint8_t> bytes, std::string* out_error) {
  const auto fail = [&](const std::string& message) -> std::optional<Bundle> {
    if (out_error)
      *out_error = message;
    return std::nullopt;
  };
  if (bytes.size() < kHeaderBytes)
    return fail("not a Motion LOD bundle: " + std::to_string(bytes.size()) + " bytes are fewer than a header");
  if (std::memcmp(bytes.data(), kBundleMagic, sizeof kBundleMagic) != 0)
    return fail("not a Motion LOD bundle (no MLODBNDL magic)");
  Reader header(bytes.subspan(8, kHeaderBytes - 8), "header");
  const std::uint32_t version = header.u32();
  const std::uint32_t count = header.u32();
  const std::uint64_t total = header.u64();
  if (version == 1)
    return fail("bundle format version 1: it stores clip sources, which this reader no longer builds; export the "
                "character again for version " + std::to_string(kBundleVersion) +
                " (the compressed clips the runtime plays)");
  if (version != kBundleVersion)
    return fail("bundle format version " + std::to_string(version) + ": this reader reads version " +
                std::to_string(kBundleVersion) + (version > kBundleVersion ? " (written by a newer exporter)" : ""));
  if (total != bytes.size())
    return fail("truncated or padded: the header says " + std::to_string(total) + " bytes, the data has " +
                std::to_string(bytes.size()));
  // (a header alone, or with less than the table's CRC-32 after it, has no room for a table)
  if (count < 2 || count > kMaxLevels + 1 || bytes.size() < kHeaderBytes + 4 ||
      (bytes.size() - kHeaderBytes - 4) / kSectionEntryBytes < count)
    return fail("corrupt section table (" + std::to_string(count) + " sections)");
  const std::size_t tableEnd = kHeaderBytes + std::size_t(count) * kSectionEntryBytes;
  Reader tableCrc(bytes.subspan(tableEnd, 4), "section table");
  if (tableCrc.u32() != crc32(bytes.first(tableEnd)))
    return fail("corrupt header or section table (CRC-32 mismatch)");
  Reader table(bytes.subspan(kHeaderBytes, tableEnd - kHeaderBytes), "section table");
  Bundle bundle;
  std::size_t expected = tableEnd + 4;
  std::uint32_t levelCount = 0;
  for (std::uint32_t i = 0; i < count; ++i) {
    const std::uint32_t type = table.u32();
    const std::uint32_t crc = table.u32();
    const std::uint64_t offset = table.u64();
    const std::uint64_t size = table.u64();
    const std::string where = "section " + std::to_string(i);
    if (offset != expected || size > bytes.size() - offset)
      return fail(where + ": at byte " + std::to_string(offset) + ", " + std::to_string(size) +
                  " bytes: outside the file or out of order");
    const std::span<const std::uint8_t> data = bytes.subspan(std::size_t(offset), std::size_t(size));
    expected = std::size_t(offset + size);
    if (crc32(data) != crc)
      return fail(where + ": corrupt (CRC-32 mismatch)");
    if ((i == 0) != (type == kSectionMeta) || (i > 0 && type != kSectionLevel))
      return fail(where + ": unexpected section type " + std::to_string(type));
    if (type == kSectionMeta) {
      Reader r(data, "metadata");
      bundle.name = r.str("name");
      bundle.source = r.str("source");
      bundle.verticalFovDegrees = r.f64();
      bundle.viewportHeightPixels = r.f64();
      bundle.boundingRadiusCm = r.f64();
      levelCount = r.u32();
      const std::uint32_t joints = r.u32();
      if (r.fits(joints, 8, "joints"))
        for (std::uint32_t j = 0; j < joints && r.ok(); ++j) {
          bundle.jointNames.push_back(r.str("joint name"));
          const std::int32_t parent = r.i32();
          bundle.jointParents.push_back(static_cast<std::int16_t>(parent < -1 || parent > 32767 ? 32767 : parent));
        }
      if (r.ok() && !r.atEnd())
        r.fail(std::to_string(r.remaining()) + " bytes left over");
      if (!r.ok())
        return fail(r.error());
      if (levelCount != count - 1)
        return fail("the metadata names " + std::to_string(levelCount) + " levels; the file holds " +
                    std::to_string(count - 1));
    } else {
      Reader r(data, "level section " + std::to_string(i));
      BundleLevel level;
      if (!readLevel(r, level))
        return fail(r.error());
      bundle.levels.push_back(std::move(level));
    }
  }
  if (std::string problem = validateBundle(bundle); !problem.empty())
    return fail("inconsistent bundle: " + problem);
  return bundle;
}

std::optional<Bundle> readBundleFile(const std::string& path, std::string* out_error) {
  // regular files only, bounded: a FIFO or /dev/zero named .mlodb must not hang the reader
  const std::optional<std::string> bytes = readInputFile(path, kMaxBundleFileBytes, out_error);
  if (!bytes)
    return std::nullopt;
  return readBundle(std::span(reinterpret_cast<const std::uint8_t*>(bytes->data()), bytes->size()), out_error);
}

std::optional<BundleLevelRuntime> buildBundleLevel(const BundleLevel& level, std::string* out_error) {
  BundleLevelRuntime out;
  std::string message;
  out.clips.reserve(level.clips.size());
  for (const BundleClip& clip : level.clips)
    out.clips.push_back(clip.clip);
  if (level.mesh) {
    out.mesh = level.mesh->build(level.jointCount(), &message);
    if (!out.mesh) {
      if (out_error)
        *out_error = "level '" + level.name + "' mesh: " + message;
      return std::nullopt;
    }
  }
  return out;
}

} // namespace mlod
