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
// Channel modes of a joint's track.
constexpr std::uint8_t kStatic = 0;      // one value for every frame
constexpr std::uint8_t kAnimated = 1;    // one value per frame
constexpr std::uint8_t kOutsideKeys = 2; // rotations: frames outside clusters, and each cluster's key once

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

bool sameBits(const glm::quat& a, const glm::quat& b) { return std::memcmp(&a, &b, sizeof(glm::quat)) == 0; }
bool sameBits(const glm::vec3& a, const glm::vec3& b) { return std::memcmp(&a, &b, sizeof(glm::vec3)) == 0; }

template <typename T>
bool constantTrack(std::span<const T> track) {
  for (const T& value : track)
    if (!sameBits(value, track.front()))
      return false;
  return true;
}

void writeVec3Track(Writer& w, std::span<const glm::vec3> track) {
  if (constantTrack(track)) {
    w.u8(kStatic);
    w.vec3(track.front());
    return;
  }
  w.u8(kAnimated);
  for (const glm::vec3& v : track)
    w.vec3(v);
}

void writeClip(Writer& w, const BundleClip& clip) {
  w.str(clip.name);
  w.f64(clip.fps);
  w.i32(clip.frameCount);
  w.u8(clip.looping ? 1 : 0);
  const std::size_t frames = static_cast<std::size_t>(clip.frameCount);
  for (std::int32_t j = 0; j < clip.jointCount; ++j) {
    const std::size_t at = static_cast<std::size_t>(j) * frames;
    std::span<const LodCluster> clusters;
    if (!clip.clusterBegin.empty())
      clusters = std::span<const LodCluster>(clip.clusters)
                     .subspan(clip.clusterBegin[std::size_t(j)], clip.clusterBegin[std::size_t(j) + 1] - clip.clusterBegin[std::size_t(j)]);
    w.u32(static_cast<std::uint32_t>(clusters.size()));
    for (const LodCluster& c : clusters) {
      w.i32(c.first);
      w.i32(c.last);
      w.i32(c.key);
    }
    const std::span<const glm::quat> rotations = std::span<const glm::quat>(clip.rotations).subspan(at, frames);
    // inside a cluster every rotation is the key's (M'(t)): store it once, when that holds bit for bit
    bool elide = !clusters.empty();
    for (const LodCluster& c : clusters)
      for (std::int32_t f = c.first; elide && f <= c.last; ++f)
        elide = sameBits(rotations[std::size_t(f)], rotations[std::size_t(c.key)]);
    if (constantTrack(rotations)) {
      w.u8(kStatic);
      w.quat(rotations.front());
    } else if (elide) {
      w.u8(kOutsideKeys);
      std::size_t next = 0;
      for (std::int32_t f = 0; f < clip.frameCount; ++f) {
        if (next < clusters.size() && f == clusters[next].first) {
          w.quat(rotations[std::size_t(clusters[next].key)]);
          f = clusters[next].last;
          ++next;
          continue;
        }
        w.quat(rotations[std::size_t(f)]);
      }
    } else {
      w.u8(kAnimated);
      for (const glm::quat& q : rotations)
        w.quat(q);
    }
    writeVec3Track(w, std::span<const glm::vec3>(clip.translations).subspan(at, frames));
    writeVec3Track(w, std::span<const glm::vec3>(clip.scales).subspan(at, frames));
  }
}

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
    writeClip(w, clip);
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

void readVec3Track(Reader& r, std::vector<glm::vec3>& out, std::size_t frames, const char* what) {
  const std::uint8_t mode = r.u8();
  if (mode == kStatic) {
    out.insert(out.end(), frames, r.vec3());
  } else if (mode == kAnimated) {
    if (!r.fits(frames, 12, what))
      return;
    for (std::size_t f = 0; f < frames; ++f)
      out.push_back(r.vec3());
  } else {
    r.fail(std::string(what) + ": unknown track mode " + std::to_string(mode));
  }
}

void readClip(Reader& r, BundleClip& clip, int joints, std::uint64_t& budget) {
  clip.name = r.str("clip name");
  clip.fps = r.f64();
  clip.frameCount = r.i32();
  const std::uint8_t looping = r.u8();
  if (!r.ok())
    return;
  if (!(std::isfinite(clip.fps) && clip.fps > 0.0 && clip.fps <= 10000.0))
    return r.fail("clip '" + clip.name + "': a frame rate of " + std::to_string(clip.fps));
  if (looping > 1)
    return r.fail("clip '" + clip.name + "': a looping flag of " + std::to_string(looping));
  clip.looping = looping == 1;
  clip.jointCount = joints;
  // every joint takes at least 4 (clusters) + 3 x 13 (static channels) bytes
  if (clip.frameCount < 1 || !r.fits(std::uint64_t(joints), 43, "clip joints"))
    return r.fail("clip '" + clip.name + "': " + std::to_string(clip.frameCount) + " frames");
  const std::size_t frames = static_cast<std::size_t>(clip.frameCount);
  // a static joint costs 43 bytes whatever the frame count: bound what the tracks may expand to
  const std::uint64_t jointFrames = std::uint64_t(frames) * std::uint64_t(joints);
  if (jointFrames > kMaxBundleJointFrames - budget)
    return r.fail("clip '" + clip.name + "': " + std::to_string(frames) + " frames x " + std::to_string(joints) +
                  " joints would take the bundle past " + std::to_string(kMaxBundleJointFrames) + " joint-frames");
  budget += jointFrames;
  clip.rotations.reserve(frames * std::size_t(joints));
  clip.translations.reserve(frames * std::size_t(joints));
  clip.scales.reserve(frames * std::size_t(joints));
  clip.clusterBegin.push_back(0);
  for (int j = 0; j < joints && r.ok(); ++j) {
    const std::uint32_t count = r.u32();
    if (!r.fits(count, 12, "clusters"))
      return;
    const std::size_t begin = clip.clusters.size();
    std::int32_t previousLast = -1;
    for (std::uint32_t c = 0; c < count; ++c) {
      LodCluster cluster;
      cluster.first = r.i32();
      cluster.last = r.i32();
      cluster.key = r.i32();
      if (cluster.first <= previousLast || std::int64_t(cluster.last) - cluster.first < 2 || cluster.last >= clip.frameCount ||
          cluster.key < cluster.first || cluster.key > cluster.last)
        return r.fail("clip '" + clip.name + "' joint " + std::to_string(j) + ": cluster [" +
                      std::to_string(cluster.first) + ", " + std::to_string(cluster.last) + "] key " +
                      std::to_string(cluster.key) + " is not sorted, disjoint, >= 3 frames, key inside");
      previousLast = cluster.last;
      clip.clusters.push_back(cluster);
    }
    clip.clusterBegin.push_back(static_cast<std::uint32_t>(clip.clusters.size()));
    const std::uint8_t mode = r.u8();
    if (mode == kStatic) {
      clip.rotations.insert(clip.rotations.end(), frames, r.quat());
    } else if (mode == kAnimated) {
      if (!r.fits(frames, 16, "rotations"))
        return;
      for (std::size_t f = 0; f < frames; ++f)
        clip.rotations.push_back(r.quat());
    } else if (mode == kOutsideKeys) {
      std::size_t next = begin;
      for (std::int32_t f = 0; f < clip.frameCount && r.ok(); ++f) {
        if (next < clip.clusters.size() && f == clip.clusters[next].first) {
          const LodCluster& cluster = clip.clusters[next++];
          clip.rotations.insert(clip.rotations.end(), std::size_t(cluster.last - cluster.first + 1), r.quat());
          f = cluster.last;
          continue;
        }
        clip.rotations.push_back(r.quat());
      }
    } else {
      return r.fail("clip '" + clip.name + "': unknown rotation mode " + std::to_string(mode));
    }
    readVec3Track(r, clip.translations, frames, "translations");
    readVec3Track(r, clip.scales, frames, "scales");
  }
  if (!r.ok())
    return;
  if (clip.clusters.empty())
    clip.clusterBegin.clear(); // no clusters: full detail, as the writer had it or not
}

bool readLevel(Reader& r, BundleLevel& level, std::uint64_t& budget) {
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
  if (!r.fits(clips, 20, "clips"))
    return false;
  level.clips.resize(clips);
  for (BundleClip& clip : level.clips) {
    readClip(r, clip, static_cast<int>(joints), budget);
    if (!r.ok())
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

LodClipSource BundleClip::source() const {
  LodClipSource s;
  s.fps = fps;
  s.frameCount = frameCount;
  s.jointCount = jointCount;
  s.looping = looping;
  s.rotations = rotations;
  s.translations = translations;
  s.scales = scales;
  s.clusters = clusters;
  s.clusterBegin = clusterBegin;
  return s;
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
      jointFrames += std::uint64_t(std::max(clip.frameCount, 0)) * std::uint64_t(std::max(clip.jointCount, 0));
  if (jointFrames > kMaxBundleJointFrames)
    return "the clips hold " + std::to_string(jointFrames) + " joint-frames, more than a bundle may (" +
           std::to_string(kMaxBundleJointFrames) + ")";
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
      const std::size_t tracks = std::size_t(std::max(clip.frameCount, 0)) * n;
      if (clip.jointCount != std::int32_t(n) || clip.rotations.size() != tracks || clip.translations.size() != tracks ||
          clip.scales.size() != tracks)
        return what + "clip '" + clip.name + "' does not match the level's " + std::to_string(n) + " joints";
      if (!clip.clusterBegin.empty() && (clip.clusterBegin.size() != n + 1 || clip.clusterBegin.back() != clip.clusters.size()))
        return what + "clip '" + clip.name + "' has a cluster index of the wrong size";
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
  if (version != kBundleVersion)
    return fail("bundle format version " + std::to_string(version) + ": this reader reads version " +
                std::to_string(kBundleVersion) + (version > kBundleVersion ? " (written by a newer exporter)" : ""));
  if (total != bytes.size())
    return fail("truncated or padded: the header says " + std::to_string(total) + " bytes, the data has " +
                std::to_string(bytes.size()));
  if (count < 2 || count > kMaxLevels + 1 || (bytes.size() - kHeaderBytes - 4) / kSectionEntryBytes < count)
    return fail("corrupt section table (" + std::to_string(count) + " sections)");
  const std::size_t tableEnd = kHeaderBytes + std::size_t(count) * kSectionEntryBytes;
  Reader tableCrc(bytes.subspan(tableEnd, 4), "section table");
  if (tableCrc.u32() != crc32(bytes.first(tableEnd)))
    return fail("corrupt header or section table (CRC-32 mismatch)");
  Reader table(bytes.subspan(kHeaderBytes, tableEnd - kHeaderBytes), "section table");
  Bundle bundle;
  std::size_t expected = tableEnd + 4;
  std::uint32_t levelCount = 0;
  std::uint64_t jointFrames = 0; // expanded so far (kMaxBundleJointFrames)
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
      if (!readLevel(r, level, jointFrames))
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

std::optional<BundleLevelRuntime> buildBundleLevel(const BundleLevel& level, std::string* out_error, int blendFrames) {
  BundleLevelRuntime out;
  std::string message;
  for (const BundleClip& clip : level.clips) {
    LodClipSource source = clip.source();
    source.blendFrames = blendFrames;
    if (level.parents.size() == static_cast<std::size_t>(clip.jointCount))
      source.parents = level.parents;
    std::optional<LodClip> built = LodClip::build(source, &message);
    if (!built) {
      if (out_error)
        *out_error = "level '" + level.name + "' clip '" + clip.name + "': " + message;
      return std::nullopt;
    }
    out.clips.push_back(std::move(*built));
  }
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
