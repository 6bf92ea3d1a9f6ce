#include "runtime/lod_clip.h"

#include "runtime/transform.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace mlod {

namespace {

bool fail(std::string* out_error, const std::string& message) {
  if (out_error)
    *out_error = message;
  return false;
}

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
bool finite(const glm::quat& q) {
  return std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z) && std::isfinite(q.w);
}

// One value throughout, bit for bit: the rotation is static (a lossless saving that full
// detail gets too).
bool constantTrack(std::span<const glm::quat> track) {
  for (const glm::quat& value : track)
    if (std::memcmp(&value, &track[0], sizeof(glm::quat)) != 0)
      return false;
  return true;
}

// One value throughout but for float rounding (within 1e-6 of its size, and far below the
// precision): the translation or scale is static, its first value.
bool constantTrack(std::span<const glm::vec3> track, double precisionCm) {
  const glm::vec3 first = track[0];
  const double size = std::max({1.0, double(std::abs(first.x)), double(std::abs(first.y)), double(std::abs(first.z))});
  const double rounding = std::min(1e-6 * size, 1e-3 * precisionCm);
  for (const glm::vec3& value : track)
    if (std::abs(double(value.x) - first.x) > rounding || std::abs(double(value.y) - first.y) > rounding ||
        std::abs(double(value.z) - first.z) > rounding)
      return false;
  return true;
}

glm::quat nlerp(const glm::quat& a, const glm::quat& b, float t) {
  const glm::quat q(a.w + (b.w - a.w) * t, a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t, a.z + (b.z - a.z) * t);
  return q * (1.0f / std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w));
}

bool checkSource(const LodClipSource& source, std::string* out_error) {
  if (!std::isfinite(source.fps) || source.fps <= 0.0 || source.fps > 1e6)
    return fail(out_error, "frame rate " + std::to_string(source.fps) + " is not in (0, 1e6] fps");
  if (source.frameCount < 1)
    return fail(out_error, "the clip has no frames");
  if (source.jointCount < 1 || source.jointCount > 32767)
    return fail(out_error, "joint count " + std::to_string(source.jointCount) + " is not in [1, 32767]");
  const std::size_t n = static_cast<std::size_t>(source.jointCount) * static_cast<std::size_t>(source.frameCount);
  if (n > (std::size_t{1} << 29))
    return fail(out_error, "the clip has more than 2^29 joint-frames");
  if (source.rotations.size() != n || source.translations.size() != n || source.scales.size() != n)
    return fail(out_error, "tracks must hold joints x frames = " + std::to_string(n) + " values each");
  for (std::size_t i = 0; i < n; ++i) {
    if (!finite(source.rotations[i]) || !finite(source.translations[i]) || !finite(source.scales[i]))
      return fail(out_error, "a track holds a value that is not finite");
    if (std::abs(glm::length(source.rotations[i]) - 1.0f) > 1e-3f)
      return fail(out_error, "a rotation is not a unit quaternion");
  }
  if (!std::isfinite(source.precisionCm) || source.precisionCm <= 0.0 || source.precisionCm > 1e3)
    return fail(out_error, "precision " + std::to_string(source.precisionCm) + " cm is not in (0, 1000]");
  if (!source.parents.empty()) {
    if (source.parents.size() != static_cast<std::size_t>(source.jointCount))
      return fail(out_error, "parents must hold one entry per joint");
    for (std::size_t j = 0; j < source.parents.size(); ++j)
      if (source.parents[j] < -1 || source.parents[j] >= static_cast<std::int32_t>(j))
        return fail(out_error, "joint " + std::to_string(j) + "'s parent does not come before it");
  }
  if (!std::isfinite(source.evaluationsPerSecond) || source.evaluationsPerSecond <= 0.0 ||
      source.evaluationsPerSecond > 1e6)
    return fail(out_error, "evaluations per second " + std::to_string(source.evaluationsPerSecond) +
                               " is not in (0, 1e6]");
  if (source.blendFrames < 0 || source.blendFrames > kMaxBlendFrames)
    return fail(out_error, "blend frames " + std::to_string(source.blendFrames) + " is not in [0, " +
                               std::to_string(kMaxBlendFrames) + "]");
  if (source.clusterBegin.empty()) {
    if (!source.clusters.empty())
      return fail(out_error, "clusters are given without clusterBegin");
    return true;
  }
  if (source.clusterBegin.size() != static_cast<std::size_t>(source.jointCount) + 1 || source.clusterBegin[0] != 0 ||
      source.clusterBegin.back() != source.clusters.size())
    return fail(out_error, "clusterBegin must hold joints + 1 offsets from 0 to the cluster count");
  for (int j = 0; j < source.jointCount; ++j) {
    const std::uint32_t begin = source.clusterBegin[static_cast<std::size_t>(j)];
    const std::uint32_t end = source.clusterBegin[static_cast<std::size_t>(j) + 1];
    if (end < begin)
      return fail(out_error, "clusterBegin is not sorted");
    std::int32_t previousLast = -1;
    for (std::uint32_t c = begin; c < end; ++c) {
      const LodCluster& cluster = source.clusters[c];
      if (cluster.first <= previousLast || cluster.last - cluster.first + 1 < 3 || cluster.last >= source.frameCount ||
          cluster.key < cluster.first || cluster.key > cluster.last)
        return fail(out_error, "joint " + std::to_string(j) + ": clusters must be sorted, disjoint, >= 3 frames, "
                                   "inside the clip, with the key inside");
      previousLast = cluster.last;
    }
  }
  return true;
}

// How far an error in each joint's channels moves a joint or a shell point (LodClip's
// header): per joint the lever of its rotation (cm: the longest chain of bones below it in
// model space, plus the shell), the factor of its translation (its parents' scale) and the
// animated channels on the longest path from a root.
struct Levers {
  std::vector<double> rotation;
  std::vector<double> translation;
  int pathChannels = 1;
};

Levers leversOf(const LodClipSource& source, std::span<const std::uint8_t> flags) {
  constexpr double kShellCm = 3.0;
  const std::size_t joints = static_cast<std::size_t>(source.jointCount);
  const std::size_t frames = static_cast<std::size_t>(source.frameCount);
  std::vector<double> bone(joints, 0.0), scale(joints, 1.0);
  for (std::size_t j = 0; j < joints; ++j)
    for (std::size_t f = 0; f < frames; ++f) {
      bone[j] = std::max(bone[j], double(glm::length(source.translations[j * frames + f])));
      const glm::vec3 s = glm::abs(source.scales[j * frames + f]);
      scale[j] = std::max({scale[j], double(s.x), double(s.y), double(s.z)});
    }
  const auto channels = [&](std::size_t j) {
    const std::uint8_t f = flags[j];
    return int((f & LodClip::kRotationAnimated) != 0) + int((f & LodClip::kTranslationAnimated) != 0) +
           int((f & LodClip::kScaleAnimated) != 0);
  };
  Levers out;
  out.rotation.assign(joints, kShellCm);
  out.translation.assign(joints, 1.0);
  if (source.parents.size() == joints) {
    // accumulated scale (the largest per joint, multiplied down the chain)
    std::vector<double> accumulated(joints, 1.0);
    std::vector<int> path(joints, 0);
    for (std::size_t j = 0; j < joints; ++j) {
      const int p = source.parents[j];
      const double above = p >= 0 ? accumulated[static_cast<std::size_t>(p)] : 1.0;
      accumulated[j] = above * scale[j];
      out.translation[j] = above;
      path[j] = channels(j) + (p >= 0 ? path[static_cast<std::size_t>(p)] : 0);
      out.pathChannels = std::max(out.pathChannels, path[j]);
    }
    std::vector<double> below(joints, 0.0);
    for (std::size_t j = joints; j-- > 1;) {
      const int p = source.parents[j];
      if (p >= 0)
        below[static_cast<std::size_t>(p)] =
            std::max(below[static_cast<std::size_t>(p)], accumulated[static_cast<std::size_t>(p)] * bone[j] + below[j]);
    }
    for (std::size_t j = 0; j < joints; ++j)
      out.rotation[j] = kShellCm + below[j];
  } else {
    // every joint may lie below every other
    double reach = kShellCm, product = 1.0;
    int all = 0;
    for (std::size_t j = 0; j < joints; ++j) {
      product *= scale[j];
      all += channels(j);
    }
    for (std::size_t j = 0; j < joints; ++j)
      reach += product * bone[j];
    std::fill(out.rotation.begin(), out.rotation.end(), reach);
    std::fill(out.translation.begin(), out.translation.end(), product);
    out.pathChannels = std::max(all, 1);
  }
  return out;
}

glm::vec4 asVec4(const glm::quat& q) { return glm::vec4(q.x, q.y, q.z, q.w); }

} // namespace

std::optional<LodClip> LodClip::build(const LodClipSource& source, std::string* out_error) {
  if (!checkSource(source, out_error))
    return std::nullopt;
  LodClip clip;
  clip.m_fps = source.fps;
  clip.m_frameCount = source.frameCount;
  clip.m_jointCount = source.jointCount;
  clip.m_looping = source.looping;
  clip.m_precisionCm = source.precisionCm;
  clip.m_blendFrames = std::clamp(source.blendFrames, 0, kMaxBlendFrames);
  const std::size_t joints = static_cast<std::size_t>(source.jointCount);
  const std::size_t frames = static_cast<std::size_t>(source.frameCount);
  clip.m_flags.assign(joints, 0);
  clip.m_staticRotation.resize(joints);
  clip.m_staticTranslation.resize(joints);
  clip.m_staticScale.resize(joints);
  clip.m_rotationStream.assign(joints, -1);
  clip.m_translationStream.assign(joints, -1);
  clip.m_scaleStream.assign(joints, -1);
  clip.m_regionBegin.assign(joints + 1, 0);

  for (std::size_t j = 0; j < joints; ++j) {
    const std::span<const glm::vec3> scales = source.scales.subspan(j * frames, frames);
    std::uint8_t flags = 0;
    if (!constantTrack(source.rotations.subspan(j * frames, frames)))
      flags |= kRotationAnimated;
    if (!constantTrack(source.translations.subspan(j * frames, frames), source.precisionCm))
      flags |= kTranslationAnimated;
    if (!constantTrack(scales, source.precisionCm))
      flags |= kScaleAnimated;
    if ((flags & kScaleAnimated) || scales[0] != glm::vec3(1.0f))
      flags |= kScaled;
    clip.m_flags[j] = flags;
    clip.m_staticRotation[j] = source.rotations[j * frames];
    clip.m_staticTranslation[j] = source.translations[j * frames];
    clip.m_staticScale[j] = scales[0];
  }

  const Levers levers = leversOf(source, clip.m_flags);
  const double share = source.precisionCm / levers.pathChannels;
  double worstCm = 0.0;
  std::vector<glm::vec4> values;
  std::vector<Region> regions; // every joint's, then packed into m_regionWords
  const auto addStream = [&](bool rotation, double arm) {
    double error = 0.0;
    const int stream = clip.m_streams.add(values, rotation, share / arm, &error);
    worstCm = std::max(worstCm, error * arm * levers.pathChannels);
    return stream;
  };
  // A channel whose decoded values are one value throughout is static at that value (it
  // varied by less than its tolerance): what a reader sees never moves, so nothing samples it.
  const auto keptIfMoving = [&](int stream, std::uint8_t flag, std::size_t j) {
    if (!clip.m_streams.constant(stream))
      return stream;
    const glm::vec4 value = clip.m_streams.value(stream, 0);
    if (flag == kRotationAnimated)
      clip.m_staticRotation[j] = internal::toQuat(value);
    else if (flag == kTranslationAnimated)
      clip.m_staticTranslation[j] = glm::vec3(value);
    else
      clip.m_staticScale[j] = glm::vec3(value);
    clip.m_streams.dropLast();
    clip.m_flags[j] = static_cast<std::uint8_t>(clip.m_flags[j] & ~flag);
    return -1;
  };
  const int n = clip.m_blendFrames;
  // evaluations a frozen frame interval is held for (the header's "Held or sampled")
  const double heldPerFrame = source.evaluationsPerSecond / source.fps;
  std::vector<glm::quat> shown(frames);
  std::vector<std::uint8_t> held(frames);
  std::vector<glm::quat> offset(n > 0 ? frames : 0);
  std::vector<LodCluster> spans;
  for (std::size_t j = 0; j < joints; ++j) {
    const std::uint8_t flags = clip.m_flags[j];
    clip.m_regionBegin[j] = static_cast<std::uint32_t>(regions.size());
    if (flags & kRotationAnimated) {
      // a joint that never turns is the same at every level: its clusters change nothing
      const glm::quat* q = source.rotations.data() + j * frames;
      std::span<const LodCluster> given;
      if (!source.clusterBegin.empty())
        given = source.clusters.subspan(source.clusterBegin[j], source.clusterBegin[j + 1] - source.clusterBegin[j]);
      // what the joint shows at each frame (the header's "Unfreeze blending"): M', then
      // each window's offset, older windows outermost; `held`: the key, untouched
      std::copy_n(q, frames, shown.begin());
      std::fill(held.begin(), held.end(), std::uint8_t{0});
      for (const LodCluster& cluster : given)
        for (std::int32_t i = cluster.first; i <= cluster.last; ++i) {
          shown[static_cast<std::size_t>(i)] = q[cluster.key];
          held[static_cast<std::size_t>(i)] = 1;
        }
      if (n > 0) {
        std::fill(offset.begin(), offset.end(), glm::quat(1.0f, 0.0f, 0.0f, 0.0f));
        for (const LodCluster& cluster : given) {
          if (cluster.last >= source.frameCount - 1)
            continue; // it reaches the clip's end: nothing to leave
          const glm::quat exit = positiveW(q[cluster.key] * glm::inverse(q[cluster.last]));
          const std::int32_t end = std::min(cluster.last + n, source.frameCount);
          for (std::int32_t i = cluster.last + 1; i < end; ++i) {
            const float weight = 1.0f - static_cast<float>(i - cluster.last) / static_cast<float>(n);
            offset[static_cast<std::size_t>(i)] = offset[static_cast<std::size_t>(i)] * scaleOffset(exit, weight);
            held[static_cast<std::size_t>(i)] = 0;
          }
        }
        for (std::size_t i = 0; i < frames; ++i)
          shown[i] = glm::normalize(offset[i] * shown[i]);
      }
      // the frozen frames of each cluster (a cluster's frames minus those an earlier window
      // reaches: a suffix of it), kept where held for kMinHeldEvaluations or more (the
      // header's "Held or sampled"); the frames of a cluster not kept are stored as they
      // show (its key), like any frame outside a cluster
      spans.clear();
      for (const LodCluster& cluster : given) {
        std::int32_t first = cluster.first;
        while (first <= cluster.last && !held[static_cast<std::size_t>(first)])
          ++first;
        if (cluster.last - first >= 1 && (cluster.last - first) * heldPerFrame >= kMinHeldEvaluations)
          spans.push_back(LodCluster{first, cluster.last, cluster.key});
      }
      values.clear();
      // regions: each frozen span (or frame 0 alone) and the frames after it up to the next
      std::size_t next = 0;
      std::int32_t frame = 0;
      while (frame < source.frameCount) {
        Region region;
        region.first = frame;
        region.entry = static_cast<std::uint32_t>(values.size());
        std::int32_t last = frame;
        if (next < spans.size() && spans[next].first == frame) {
          last = spans[next++].last;
          values.push_back(asVec4(q[spans[next - 1].key]));
        } else {
          values.push_back(asVec4(shown[static_cast<std::size_t>(frame)]));
        }
        const std::int32_t end = next < spans.size() ? spans[next].first : source.frameCount;
        for (std::int32_t i = last + 1; i < end; ++i)
          values.push_back(asVec4(shown[static_cast<std::size_t>(i)]));
        regions.push_back(region);
        frame = end;
      }
      regions.push_back(Region{source.frameCount, static_cast<std::uint32_t>(values.size())});
      clip.m_rotationStream[j] = keptIfMoving(addStream(true, levers.rotation[j]), kRotationAnimated, j);
      if (clip.m_rotationStream[j] >= 0) {
        clip.m_clusterCount += static_cast<int>(given.size());
        if (spans.empty())
          clip.m_flags[j] = static_cast<std::uint8_t>(clip.m_flags[j] | kEveryFrame);
      } else {
        regions.resize(clip.m_regionBegin[j]);
      }
    }
  }
  clip.m_regionBegin[joints] = static_cast<std::uint32_t>(regions.size());
  // then the translations and scales: the rotation streams come first, the i-th animated
  // rotation's stream is stream i (the evaluator walks them in order; storageProblem())
  const auto addVectors = [&](std::span<const glm::vec3> track, double arm) {
    values.clear();
    for (const glm::vec3& v : track)
      values.emplace_back(v, 0.0f);
    return addStream(false, arm);
  };
  for (std::size_t j = 0; j < joints; ++j) {
    const std::uint8_t flags = clip.m_flags[j];
    if (flags & kTranslationAnimated)
      clip.m_translationStream[j] = keptIfMoving(
          addVectors(source.translations.subspan(j * frames, frames), levers.translation[j]), kTranslationAnimated, j);
    if (flags & kScaleAnimated)
      clip.m_scaleStream[j] = keptIfMoving(
          addVectors(source.scales.subspan(j * frames, frames), levers.rotation[j] * levers.translation[j]),
          kScaleAnimated, j);
    std::uint8_t& kept = clip.m_flags[j];
    if (!(kept & kScaleAnimated) && clip.m_staticScale[j] == glm::vec3(1.0f))
      kept = static_cast<std::uint8_t>(kept & ~kScaled);
  }
  clip.deriveJointLists();
  // 16 bits each where they fit (a first frame or an entry is at most frameCount)
  clip.m_narrowRegions = source.frameCount <= 0xffff;
  clip.m_regionWords.reserve(clip.m_narrowRegions ? regions.size() : 2 * regions.size());
  for (const Region& region : regions) {
    if (clip.m_narrowRegions) {
      clip.m_regionWords.push_back(static_cast<std::uint32_t>(region.first) | (region.entry << 16));
    } else {
      clip.m_regionWords.push_back(static_cast<std::uint32_t>(region.first));
      clip.m_regionWords.push_back(region.entry);
    }
  }
  clip.m_streams.finish();
  clip.m_encodedErrorCm = worstCm;
  return clip;
}

void LodClip::deriveJointLists() {
  m_rotationJoints.clear();
  m_vectorJoints.clear();
  m_scaled = false;
  for (std::size_t j = 0; j < m_flags.size(); ++j) {
    const std::uint8_t f = m_flags[j];
    m_scaled = m_scaled || (f & kScaled);
    if (f & kRotationAnimated)
      m_rotationJoints.push_back(static_cast<std::int16_t>(j));
    if (f & (kTranslationAnimated | kScaleAnimated))
      m_vectorJoints.push_back(static_cast<std::int16_t>(j));
  }
}

std::string LodClip::storageProblem() const {
  if (!std::isfinite(m_fps) || m_fps <= 0.0 || m_fps > 1e6)
    return "frame rate " + std::to_string(m_fps) + " is not in (0, 1e6] fps";
  if (m_frameCount < 1)
    return "the clip has no frames";
  if (m_jointCount < 1 || m_jointCount > 32767)
    return "joint count " + std::to_string(m_jointCount) + " is not in [1, 32767]";
  if (m_blendFrames < 0 || m_blendFrames > kMaxBlendFrames)
    return "blend frames " + std::to_string(m_blendFrames) + " is not in [0, " + std::to_string(kMaxBlendFrames) + "]";
  if (!std::isfinite(m_precisionCm) || m_precisionCm <= 0.0 || m_precisionCm > 1e3)
    return "precision " + std::to_string(m_precisionCm) + " cm is not in (0, 1000]";
  if (!std::isfinite(m_encodedErrorCm) || m_encodedErrorCm < 0.0)
    return "an encoded error of " + std::to_string(m_encodedErrorCm) + " cm";
  if (m_clusterCount < 0)
    return "a cluster count of " + std::to_string(m_clusterCount);
  const std::size_t joints = static_cast<std::size_t>(m_jointCount);
  if (m_flags.size() != joints || m_staticRotation.size() != joints || m_staticTranslation.size() != joints ||
      m_staticScale.size() != joints || m_rotationStream.size() != joints || m_translationStream.size() != joints ||
      m_scaleStream.size() != joints || m_regionBegin.size() != joints + 1)
    return "per-joint arrays of the wrong size";
  if (std::string problem = m_streams.storageProblem(); !problem.empty())
    return problem;
  if (m_narrowRegions != (m_frameCount <= 0xffff))
    return "regions stored in the wrong width for " + std::to_string(m_frameCount) + " frames";
  const std::size_t regions = m_narrowRegions ? m_regionWords.size() : m_regionWords.size() / 2;
  if (!m_narrowRegions && m_regionWords.size() % 2 != 0)
    return "an odd number of wide region words";
  if (m_regionBegin[0] != 0 || m_regionBegin[joints] != regions)
    return "the region index does not span the regions";
  // each stream feeds one channel
  std::vector<std::uint8_t> used(static_cast<std::size_t>(m_streams.streamCount()), 0);
  const auto streamProblem = [&](int s, bool animated, bool rotation, std::uint32_t entries) -> std::string {
    if (!animated)
      return s == -1 ? std::string() : "a static channel with a stream";
    if (s < 0 || s >= m_streams.streamCount() || used[static_cast<std::size_t>(s)])
      return "an animated channel without a stream of its own";
    used[static_cast<std::size_t>(s)] = 1;
    const internal::Stream& stream = m_streams.stream(s);
    if (stream.rotation != rotation)
      return "a stream of the wrong kind";
    if (stream.entries != entries)
      return "a stream of " + std::to_string(stream.entries) + " entries where " + std::to_string(entries) +
             " are addressed";
    return {};
  };
  for (std::size_t j = 0; j < joints; ++j) {
    const std::string joint = "joint " + std::to_string(j) + ": ";
    const std::uint8_t f = m_flags[j];
    if (f & ~(kAnimated | kScaled | kEveryFrame))
      return joint + "unknown flags " + std::to_string(f);
    if ((f & kAnimated) && m_frameCount < 2)
      return joint + "animated in a one-frame clip";
    if (!finite(m_staticRotation[j]) || !finite(m_staticTranslation[j]) || !finite(m_staticScale[j]))
      return joint + "a static value that is not finite";
    const bool scaled = (f & kScaleAnimated) || m_staticScale[j] != glm::vec3(1.0f);
    if (scaled != ((f & kScaled) != 0))
      return joint + "a scaled flag that does not match its scale";
    if (m_regionBegin[j + 1] < m_regionBegin[j])
      return joint + "the region index is not sorted";
    const std::uint32_t begin = m_regionBegin[j], end = m_regionBegin[j + 1];
    const bool rotation = (f & kRotationAnimated) != 0;
    if (!rotation) {
      if (end != begin || (f & kEveryFrame))
        return joint + "regions or every-frame storage for a static rotation";
    } else {
      // regions from frame 0 and entry 0, first frames rising, each region's entries
      // between 1 and its frames, to the sentinel {frameCount, entries}
      if (end - begin < 2 || ((f & kEveryFrame) && end - begin != 2))
        return joint + std::to_string(end - begin) + " region words for an animated rotation";
      if (regionFirst(begin) != 0 || regionEntry(begin) != 0)
        return joint + "its first region is not at frame 0, entry 0";
      for (std::uint32_t r = begin; r + 1 < end; ++r) {
        const std::int64_t frames = std::int64_t(regionFirst(r + 1)) - regionFirst(r);
        const std::int64_t entries = std::int64_t(regionEntry(r + 1)) - regionEntry(r);
        if (frames < 1 || entries < 1 || entries > frames)
          return joint + "region " + std::to_string(r - begin) + " holds " + std::to_string(frames) + " frames and " +
                 std::to_string(entries) + " entries";
      }
      if (regionFirst(end - 1) != m_frameCount)
        return joint + "its regions do not end at the clip's end";
      if ((f & kEveryFrame) && regionEntry(end - 1) != static_cast<std::uint32_t>(m_frameCount))
        return joint + "every-frame storage with fewer entries than frames";
    }
    const std::uint32_t frames = static_cast<std::uint32_t>(m_frameCount);
    for (const std::string& problem :
         {streamProblem(m_rotationStream[j], rotation, true, rotation ? regionEntry(end - 1) : 0),
          streamProblem(m_translationStream[j], (f & kTranslationAnimated) != 0, false, frames),
          streamProblem(m_scaleStream[j], (f & kScaleAnimated) != 0, false, frames)})
      if (!problem.empty())
        return joint + problem;
  }
  if (std::find(used.begin(), used.end(), std::uint8_t{0}) != used.end())
    return "a stream that no channel reads";
  std::int32_t rotations = 0;
  for (std::size_t j = 0; j < joints; ++j)
    if ((m_flags[j] & kRotationAnimated) && m_rotationStream[j] != rotations++)
      return "joint " + std::to_string(j) + ": its rotation's stream is not the next (rotation streams come first, in joint order)";
  return {};
}

std::size_t LodClip::byteSize() const {
  return sizeof(LodClip) + m_flags.size() * sizeof(std::uint8_t) + m_staticRotation.size() * sizeof(glm::quat) +
         (m_staticTranslation.size() + m_staticScale.size()) * sizeof(glm::vec3) +
         (m_rotationJoints.size() + m_vectorJoints.size()) * sizeof(std::int16_t) +
         (m_rotationStream.size() + m_translationStream.size() + m_scaleStream.size()) *
             sizeof(std::int32_t) +
         m_regionBegin.size() * sizeof(std::uint32_t) + m_regionWords.size() * sizeof(std::uint32_t) + m_streams.byteSize();
}

double LodClip::bytesPerSecond() const { return mlod::bytesPerSecond(byteSize(), duration()); }

int LodClip::animatedJointCount() const {
  int count = 0;
  for (const std::uint8_t flags : m_flags)
    count += (flags & kAnimated) ? 1 : 0;
  return count;
}

double LodClip::wrapped(double g, std::int64_t* out_loop) const {
  const double last = static_cast<double>(m_frameCount - 1);
  std::int64_t loop = static_cast<std::int64_t>(std::floor(g / last));
  double f = g - static_cast<double>(loop) * last;
  if (f >= last) {
    f -= last;
    ++loop;
  }
  if (out_loop)
    *out_loop = loop;
  return std::max(f, 0.0);
}

std::uint32_t LodClip::regionOf(int joint, std::int32_t i) const {
  // the last region (before the sentinel) whose first frame is at or before i
  std::uint32_t lo = regionBegin(joint), hi = regionBegin(joint + 1) - 1;
  while (hi - lo > 1) {
    const std::uint32_t mid = lo + (hi - lo) / 2;
    (regionFirst(mid) <= i ? lo : hi) = mid;
  }
  return lo;
}

bool LodClip::frozen(int joint, int i0) const {
  const std::uint8_t f = flags(joint);
  if (f & (kTranslationAnimated | kScaleAnimated))
    return false;
  if (!(f & kRotationAnimated))
    return true;
  const std::uint32_t r = regionOf(joint, i0);
  return i0 < lastOf(r);
}

glm::quat LodClip::rotationAt(int joint, double frame) const {
  if (!(flags(joint) & kRotationAnimated))
    return staticRotation(joint);
  std::int32_t i0 = 0;
  float fraction = 0.0f;
  split(frame, i0, fraction);
  const std::uint32_t r = regionOf(joint, i0);
  const std::int32_t i1 = std::min(i0 + 1, m_frameCount - 1);
  const glm::quat a = rotationEntry(joint, entryOf(r, i0));
  glm::quat b = rotationEntry(joint, entryOf(r, i1));
  if (glm::dot(a, b) < 0.0f)
    b = -b;
  return nlerp(a, b, fraction);
}

std::vector<LodClip::Cluster> LodClip::clusters(int joint) const {
  std::vector<Cluster> out;
  if (!(flags(joint) & kRotationAnimated))
    return out;
  for (std::uint32_t r = regionBegin(joint); r + 1 < regionBegin(joint + 1); ++r) {
    const std::int32_t last = lastOf(r);
    if (last == regionFirst(r))
      continue; // frame 0 alone
    Cluster cluster;
    cluster.first = regionFirst(r);
    cluster.last = last;
    cluster.key = rotationEntry(joint, regionEntry(r));
    cluster.joint = joint;
    out.push_back(cluster);
  }
  return out;
}

glm::vec3 LodClip::vectorAt(int stream, const glm::vec3& fixed, double frame) const {
  if (stream < 0)
    return fixed;
  std::int32_t i0 = 0;
  float fraction = 0.0f;
  split(frame, i0, fraction);
  const glm::vec3 a(m_streams.value(stream, static_cast<std::uint32_t>(i0)));
  const glm::vec3 b(m_streams.value(stream, static_cast<std::uint32_t>(std::min(i0 + 1, m_frameCount - 1))));
  return a + (b - a) * fraction;
}

glm::vec3 LodClip::translationAt(int joint, double frame) const {
  return vectorAt(translationStream(joint), staticTranslation(joint), frame);
}

glm::vec3 LodClip::scaleAt(int joint, double frame) const {
  return vectorAt(scaleStream(joint), staticScale(joint), frame);
}

} // namespace mlod
