#include "core/lod/held_keys.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <set>
#include <string>

namespace mlod {

namespace {

// A unit quaternion; a zero or non-finite one becomes the identity.
glm::quat unit(const glm::quat& q) {
  const float length = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
  return length > 0.0f && std::isfinite(length) ? q * (1.0f / length) : glm::quat(1.0f, 0.0f, 0.0f, 0.0f);
}

HeldRotationTrack track(const Clip& clip, int joint, std::span<const Cluster> clusters, bool removed,
                        const glm::quat& frozen, bool everyFrame) {
  HeldRotationTrack out;
  const int n = clip.frameCount;
  const auto key = [&](int frame, glm::quat q) {
    q = unit(q);
    if (!out.values.empty() && glm::dot(out.values.back(), q) < 0.0f) // the shorter way, as the runtime aligns keys
      q = -q;
    out.frames.push_back(frame);
    out.values.push_back(q);
  };
  if (removed) {
    for (int f = 0; f < n; f += everyFrame ? 1 : std::max(n - 1, 1))
      key(f, frozen);
    return out;
  }
  std::size_t next = 0; // the joint's next cluster
  for (int f = 0; f < n; ++f) {
    if (next < clusters.size() && clusters[next].first == f) {
      const Cluster& c = clusters[next++];
      const glm::quat& held = clip.rotation(joint, c.key);
      for (int g = c.first; g <= c.last; g += everyFrame ? 1 : std::max(c.last - c.first, 1))
        key(g, held);
      f = c.last;
      continue;
    }
    key(f, clip.rotation(joint, f));
  }
  return out;
}

// The distinct float arrays of a level's animations, by content and element type (the glTF
// writer shares an accessor between equal arrays of one type).
class DistinctArrays {
public:
  void add(const std::vector<float>& values, char type) {
    std::string key(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(float));
    key += type;
    if (m_seen.insert(std::move(key)).second)
      m_bytes += values.size() * sizeof(float);
  }
  void rotations(const std::vector<float>& values) {
    const std::vector<std::int16_t> shorts = quantizeRotations(values);
    std::string key(reinterpret_cast<const char*>(shorts.data()), shorts.size() * sizeof(std::int16_t));
    key += 'q';
    if (m_seen.insert(std::move(key)).second)
      m_bytes += shorts.size() * sizeof(std::int16_t);
  }
  void times(const std::vector<int>& frames, double fps) {
    std::vector<float> seconds(frames.size());
    for (std::size_t i = 0; i < frames.size(); ++i)
      seconds[i] = static_cast<float>(frames[i] / fps);
    add(seconds, 's');
  }
  std::size_t bytes() const { return m_bytes; }

private:
  std::set<std::string> m_seen;
  std::size_t m_bytes = 0;
};

} // namespace

std::vector<std::int16_t> quantizeRotations(std::span<const float> xyzw) {
  std::vector<std::int16_t> out(xyzw.size());
  for (std::size_t i = 0; i < xyzw.size(); ++i) {
    const double c = std::clamp(static_cast<double>(xyzw[i]), -1.0, 1.0);
    out[i] = static_cast<std::int16_t>(std::lround(c * kRotationQuantizationScale));
  }
  return out;
}

glm::quat dequantizeRotation(const std::int16_t* xyzw) {
  const auto c = [&](int k) { return static_cast<float>(std::max(xyzw[k] / kRotationQuantizationScale, -1.0)); };
  return unit(glm::quat(c(3), c(0), c(1), c(2)));
}

double rotationAngleDegrees(const glm::quat& a, const glm::quat& b) {
  // 4 atan2(|a - s b|, |a + s b|) for unit a, b (DESIGN.md section 4: exact near 0)
  const glm::dquat ua = glm::normalize(glm::dquat(a)), ub = glm::normalize(glm::dquat(b));
  const double s = glm::dot(ua, ub) < 0.0 ? -1.0 : 1.0;
  const glm::dquat d = ua - ub * s, e = ua + ub * s;
  return glm::degrees(4.0 * std::atan2(std::sqrt(glm::dot(d, d)), std::sqrt(glm::dot(e, e))));
}

double rotationQuantizationBoundCm(const Skeleton& skeleton, double degrees) {
  const std::size_t n = skeleton.joints.size();
  std::vector<double> depthCm(n, 0.0); // path length from the root
  double worst = 0.0;
  for (std::size_t j = 0; j < n; ++j) {
    const int parent = skeleton.joints[j].parent;
    if (parent < 0)
      continue;
    depthCm[j] = depthCm[static_cast<std::size_t>(parent)] + glm::length(skeleton.joints[j].rest.translation);
    double sum = 0.0; // path lengths from j up to each strict ancestor
    for (int a = parent; a >= 0; a = skeleton.joints[static_cast<std::size_t>(a)].parent)
      sum += depthCm[j] - depthCm[static_cast<std::size_t>(a)];
    worst = std::max(worst, sum);
  }
  return glm::radians(degrees) * worst;
}

HeldRotationTrack heldRotationTrack(const Clip& clip, int joint, std::span<const Cluster> clusters, bool removed,
                                    const glm::quat& frozen) {
  HeldRotationTrack held = track(clip, joint, clusters, removed, frozen, false);
  const std::size_t frames = static_cast<std::size_t>(std::max(clip.frameCount, 0));
  // 12 bytes a key with times of its own against 8 a frame with shared times
  if (held.frames.size() < frames && 3 * held.frames.size() >= 2 * frames)
    held = track(clip, joint, clusters, removed, frozen, true);
  return held;
}

std::vector<LevelTrack> levelTracks(const LodPackage& package, const LodPackageLevel& level, std::size_t clipIndex) {
  const Clip& clip = package.clips[clipIndex];
  const Skeleton& skeleton = package.skeleton;
  const int joints = skeleton.jointCount();
  assert(clip.jointCount == joints);
  const BoneReduction& bones = level.build.motion.bones;
  const bool reduced = static_cast<int>(bones.removed.size()) == joints;
  const ClusterSet* clusters =
      clipIndex < level.build.motion.clusters.size() ? &level.build.motion.clusters[clipIndex] : nullptr;
  if (clusters && clusters->jointCount() != joints)
    clusters = nullptr;
  // the translations and scales some clip of the package animates: every clip keys them
  std::vector<std::uint8_t> translated(static_cast<std::size_t>(joints), 0), scaled(translated);
  for (const Clip& other : package.clips)
    if (other.jointCount == joints)
      for (std::size_t j = 0; j < translated.size(); ++j) {
        translated[j] |= other.hasTranslation[j];
        scaled[j] |= other.hasScale[j];
      }
  const int n = std::max(clip.frameCount, 0);
  std::vector<int> every(static_cast<std::size_t>(n));
  for (int f = 0; f < n; ++f)
    every[static_cast<std::size_t>(f)] = f;
  const std::vector<int> ends = n > 1 ? std::vector<int>{0, n - 1} : std::vector<int>{0};
  constexpr float kMetresPerCm = 0.01f; // glTF's unit

  std::vector<LevelTrack> out;
  for (int j = 0; j < joints; ++j) {
    const std::size_t jj = static_cast<std::size_t>(j);
    const Transform& rest = skeleton.joints[jj].rest;
    const bool removed = reduced && bones.removed[jj];
    const HeldRotationTrack held =
        clip.hasRotation[jj]
            ? heldRotationTrack(clip, j,
                                clusters ? std::span<const Cluster>(clusters->joints[jj]) : std::span<const Cluster>(),
                                removed, removed ? bones.frozenRotation[jj] : glm::quat(1.0f, 0.0f, 0.0f, 0.0f))
            : heldRotationTrack(clip, j, {}, true, removed ? bones.frozenRotation[jj] : rest.rotation);
    LevelTrack rotation{j, TrackPath::Rotation, held.frames, {}};
    rotation.values.reserve(held.values.size() * 4);
    for (const glm::quat& q : held.values)
      rotation.values.insert(rotation.values.end(), {q.x, q.y, q.z, q.w});
    out.push_back(std::move(rotation));
    for (const TrackPath path : {TrackPath::Translation, TrackPath::Scale}) {
      const bool isTranslation = path == TrackPath::Translation;
      const bool animated = isTranslation ? clip.hasTranslation[jj] : clip.hasScale[jj];
      if (!animated && !(isTranslation ? translated[jj] : scaled[jj]))
        continue;
      LevelTrack track{j, path, animated ? every : ends, {}};
      track.values.reserve(track.frames.size() * 3);
      for (int f : track.frames) {
        const glm::vec3 v = isTranslation ? (animated ? clip.translation(j, f) : rest.translation) * kMetresPerCm
                                          : (animated ? clip.scale(j, f) : rest.scale);
        track.values.insert(track.values.end(), {v.x, v.y, v.z});
      }
      out.push_back(std::move(track));
    }
  }
  return out;
}

ClusterTable clusterTable(const ClusterSet& clusters) {
  ClusterTable out;
  for (int j = 0; j < clusters.jointCount(); ++j)
    for (const Cluster& cluster : clusters.joints[static_cast<std::size_t>(j)]) {
      assert(cluster.first >= 0 && cluster.first <= cluster.key && cluster.key <= cluster.last);
      out.rows.insert(out.rows.end(),
                      {static_cast<std::uint32_t>(j), static_cast<std::uint32_t>(cluster.first),
                       static_cast<std::uint32_t>(cluster.last), static_cast<std::uint32_t>(cluster.key)});
    }
  out.wide = std::any_of(out.rows.begin(), out.rows.end(), [](std::uint32_t v) { return v > 0xFFFFu; });
  return out;
}

LevelKeyBytes levelKeyBytes(const LodPackage& package, const LodPackageLevel& level) {
  LevelKeyBytes out;
  const int joints = package.skeleton.jointCount();
  if (joints == 0)
    return out;
  DistinctArrays arrays;
  for (std::size_t c = 0; c < package.clips.size(); ++c) {
    const Clip& clip = package.clips[c];
    if (clip.jointCount != joints)
      continue;
    for (const LevelTrack& track : levelTracks(package, level, c)) {
      if (track.path == TrackPath::Rotation)
        arrays.rotations(track.values);
      else
        arrays.add(track.values, '3');
      arrays.times(track.frames, clip.fps);
      if (track.path == TrackPath::Rotation)
        out.rotationKeys += track.frames.size();
    }
    if (c < level.build.motion.clusters.size() && level.build.motion.clusters[c].jointCount() == joints)
      out.clusterBytes += clusterTable(level.build.motion.clusters[c]).bytes();
  }
  out.bytes = arrays.bytes() + out.clusterBytes;
  return out;
}

} // namespace mlod
