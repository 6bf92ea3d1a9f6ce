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

// One value throughout, bit for bit: the channel is static (a lossless saving that full
// detail gets too).
template <typename T>
bool constantTrack(std::span<const T> track) {
  for (const T& value : track)
    if (std::memcmp(&value, &track[0], sizeof(T)) != 0)
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

} // namespace

std::optional<LodClip> LodClip::build(const LodClipSource& source, std::string* out_error) {
  if (!checkSource(source, out_error))
    return std::nullopt;
  LodClip clip;
  clip.m_fps = source.fps;
  clip.m_frameCount = source.frameCount;
  clip.m_jointCount = source.jointCount;
  clip.m_looping = source.looping;
  const std::size_t joints = static_cast<std::size_t>(source.jointCount);
  const std::size_t frames = static_cast<std::size_t>(source.frameCount);
  clip.m_flags.assign(joints, 0);
  clip.m_staticPair.assign(joints, 0);
  clip.m_staticTranslation.resize(joints);
  clip.m_staticScale.resize(joints);
  clip.m_locals.resize(joints);
  clip.m_translationTrack.assign(joints, -1);
  clip.m_scaleTrack.assign(joints, -1);
  clip.m_segmentBegin.assign(joints + 1, 0);
  clip.m_clusterBegin.assign(joints + 1, 0);

  for (std::size_t j = 0; j < joints; ++j) {
    const std::span<const glm::quat> rotations = source.rotations.subspan(j * frames, frames);
    const std::span<const glm::vec3> translations = source.translations.subspan(j * frames, frames);
    const std::span<const glm::vec3> scales = source.scales.subspan(j * frames, frames);
    std::uint8_t flags = 0;
    if (!constantTrack(rotations))
      flags |= kRotationAnimated;
    if (!constantTrack(translations)) {
      flags |= kTranslationAnimated;
      clip.m_translationTrack[j] = static_cast<std::int32_t>(clip.m_tracks.size());
      clip.m_tracks.insert(clip.m_tracks.end(), translations.begin(), translations.end());
    }
    if (!constantTrack(scales) || scales[0] != glm::vec3(1.0f))
      flags |= kScaled;
    if (!constantTrack(scales)) {
      flags |= kScaleAnimated;
      clip.m_scaleTrack[j] = static_cast<std::int32_t>(clip.m_tracks.size());
      clip.m_tracks.insert(clip.m_tracks.end(), scales.begin(), scales.end());
    }
    clip.m_flags[j] = flags;
    clip.m_staticPair[j] = static_cast<std::int32_t>(clip.m_rotations.size());
    clip.m_rotations.push_back(rotations[0]);
    clip.m_rotations.push_back(rotations[0]);
    clip.m_staticTranslation[j] = translations[0];
    clip.m_staticScale[j] = scales[0];
    clip.m_locals[j] = toMatrix(Transform{translations[0], rotations[0], scales[0]});

    clip.m_segmentBegin[j] = static_cast<std::uint32_t>(clip.m_segments.size());
    clip.m_clusterBegin[j] = static_cast<std::uint32_t>(clip.m_clusters.size());
    if (!(flags & kRotationAnimated)) {
      // a joint that never turns is the same at every level: its clusters change nothing
      continue;
    }
    std::span<const LodCluster> given;
    if (!source.clusterBegin.empty())
      given = source.clusters.subspan(source.clusterBegin[j], source.clusterBegin[j + 1] - source.clusterBegin[j]);
    const std::int32_t n = source.frameCount;
    const std::int32_t lastI0 = std::max(n - 2, 0);
    const std::size_t clusterBase = clip.m_clusters.size();
    // the rotation M' holds at frame i; `inCluster` = the cluster holding frame i, or -1
    std::size_t cursor = 0;
    const auto clusterOf = [&](std::int32_t i) -> int {
      while (cursor < given.size() && given[cursor].last < i)
        ++cursor;
      return cursor < given.size() && given[cursor].first <= i ? static_cast<int>(cursor) : -1;
    };
    for (const LodCluster& cluster : given) {
      Cluster out;
      out.first = cluster.first;
      out.last = cluster.last;
      out.key = cluster.key;
      out.keyPair = static_cast<std::int32_t>(clip.m_rotations.size());
      const glm::quat key = rotations[static_cast<std::size_t>(cluster.key)];
      clip.m_rotations.push_back(key);
      clip.m_rotations.push_back(key);
      out.local = static_cast<std::int32_t>(clip.m_locals.size());
      out.joint = static_cast<std::int32_t>(j);
      clip.m_locals.push_back(toMatrix(Transform{translations[0], key, scales[0]}));
      clip.m_clusters.push_back(out);
    }
    // Segments in i0 order: frozen [first, last - 1] per cluster, sampled in between.
    std::int32_t i0 = 0;
    int previous = -1;
    while (i0 <= lastI0) {
      const int c = clusterOf(i0);
      Segment segment;
      segment.first = i0;
      if (c >= 0 && i0 < given[static_cast<std::size_t>(c)].last) {
        segment.last = given[static_cast<std::size_t>(c)].last - 1;
        segment.cluster = c;
        segment.previous = c - 1;
        previous = c;
      } else {
        // sampled up to the frame before the next cluster's first frame
        const std::size_t next = c >= 0 ? static_cast<std::size_t>(c) + 1 : cursor;
        segment.last = next < given.size() ? given[next].first - 1 : lastI0;
        segment.last = std::min(segment.last, lastI0);
        segment.previous = previous;
        segment.rotation = static_cast<std::int32_t>(clip.m_rotations.size());
        // R(first .. last + 1), sign-aligned so that nlerp needs no sign test
        std::size_t scan = 0;
        glm::quat before(1.0f, 0.0f, 0.0f, 0.0f);
        for (std::int32_t i = segment.first; i <= segment.last + 1; ++i) {
          const std::int32_t frame = std::min(i, n - 1);
          while (scan < given.size() && given[scan].last < frame)
            ++scan;
          const bool clustered = scan < given.size() && given[scan].first <= frame;
          glm::quat q = rotations[static_cast<std::size_t>(clustered ? given[scan].key : frame)];
          if (i > segment.first && glm::dot(before, q) < 0.0f)
            q = -q;
          clip.m_rotations.push_back(q);
          before = q;
        }
        // the cluster that ended here, if any, blends out from its error at its last frame
        if (c >= 0 && i0 == given[static_cast<std::size_t>(c)].last) {
          const std::size_t at = static_cast<std::size_t>(segment.rotation);
          Cluster& ended = clip.m_clusters[clusterBase + static_cast<std::size_t>(c)];
          glm::quat last = rotations[static_cast<std::size_t>(i0)];
          if (glm::dot(last, clip.m_rotations[at + 1]) < 0.0f)
            last = -last;
          ended.lastRotation = last;
          ended.exitOffset = positiveW(clip.m_rotations[at] * glm::inverse(last));
          segment.previous = c;
          previous = c;
        }
      }
      if (segment.cluster >= 0) {
        const Cluster& cluster = clip.m_clusters[clusterBase + static_cast<std::size_t>(segment.cluster)];
        segment.base = cluster.keyPair;
        segment.step = 0;
        segment.local = cluster.local;
      } else {
        segment.base = segment.rotation - segment.first;
        segment.step = 1;
        segment.local = static_cast<std::int32_t>(j);
      }
      clip.m_segments.push_back(segment);
      i0 = segment.last + 1;
    }
  }
  clip.m_segmentBegin[joints] = static_cast<std::uint32_t>(clip.m_segments.size());
  clip.m_clusterBegin[joints] = static_cast<std::uint32_t>(clip.m_clusters.size());

  clip.m_blendFrames = std::clamp(source.blendFrames, 0, kMaxBlendFrames);
  clip.buildPlans();
  return clip;
}

std::size_t LodClip::byteSize() const {
  return sizeof(LodClip) + m_flags.size() * sizeof(std::uint8_t) + m_staticPair.size() * sizeof(std::int32_t) +
         m_staticTranslation.size() * sizeof(glm::vec3) + m_staticScale.size() * sizeof(glm::vec3) +
         m_locals.size() * sizeof(glm::mat4) + m_translationTrack.size() * sizeof(std::int32_t) +
         m_scaleTrack.size() * sizeof(std::int32_t) + m_tracks.size() * sizeof(glm::vec3) +
         m_segmentBegin.size() * sizeof(std::uint32_t) + m_segments.size() * sizeof(Segment) +
         m_clusterBegin.size() * sizeof(std::uint32_t) + m_clusters.size() * sizeof(Cluster) +
         m_rotations.size() * sizeof(glm::quat) + m_staticLocals.size() * sizeof(float) + planByteSize();
}

int LodClip::animatedJointCount() const {
  int count = 0;
  for (const std::uint8_t flags : m_flags)
    count += (flags & (kRotationAnimated | kTranslationAnimated | kScaleAnimated)) ? 1 : 0;
  return count;
}

std::size_t LodClip::planByteSize() const {
  return m_planBegin.size() * sizeof(std::uint32_t) + m_plans.size() * sizeof(float);
}

void LodClip::setBlendFrames(int frames) {
  frames = std::clamp(frames, 0, kMaxBlendFrames);
  if (frames == m_blendFrames)
    return;
  m_blendFrames = frames;
  if (!m_clusters.empty())
    buildPlans();
}

bool LodClip::inUnfreezeWindow(int joint, int i0, int blendFrames) const {
  if (blendFrames <= 0 || !(flags(joint) & kRotationAnimated))
    return false;
  // the latest cluster that ended at or before the segment's first frame: windows of older
  // ones end earlier (clusters are sorted); a cluster that reaches the clip's end has
  // last > i0
  const int latest = segments(joint)[static_cast<std::size_t>(findSegment(joint, i0))].previous;
  return latest >= 0 && clusters(joint)[static_cast<std::size_t>(latest)].last + blendFrames > i0;
}

void LodClip::buildPlans() {
  const std::size_t joints = static_cast<std::size_t>(m_jointCount);
  const std::int32_t planFrames = std::max(m_frameCount - 1, 1);
  const int blendFrames = m_blendFrames;
  m_scaled = false;
  for (std::size_t j = 0; j < joints; ++j)
    m_scaled = m_scaled || (m_flags[j] & kScaled);

  // every joint's static local matrix in lane layout
  m_staticLocals.assign(((joints + kLanes - 1) / kLanes) * kLanes * kLocalArrays, 0.0f);
  const auto writeLane = [](float* lane, const glm::mat4& local) {
    const float values[kLocalArrays] = {local[0][0], local[0][1], local[0][2], local[1][0], local[1][1], local[1][2],
                                        local[2][0], local[2][1], local[2][2], local[3][0], local[3][1], local[3][2]};
    for (int e = 0; e < kLocalArrays; ++e)
      lane[kLanes * e] = values[e];
  };
  for (std::size_t j = 0; j < joints; ++j)
    writeLane(m_staticLocals.data() + laneOffset(static_cast<std::uint32_t>(j)), m_locals[j]);

  // the plan of every frame i0: each joint's segment, walked forward
  const std::size_t arrays = static_cast<std::size_t>(planArrays());
  const std::size_t slotsAt = static_cast<std::size_t>(planSlotsAt());
  m_planBegin.assign(static_cast<std::size_t>(planFrames) + 1, 0);
  m_plans.clear();
  std::vector<std::size_t> cursor(joints, 0);
  struct Slot {
    std::size_t joint;
    glm::quat a, b;
  };
  std::vector<Slot> slots;
  std::vector<std::pair<std::size_t, std::int32_t>> constants; // joint, index in m_locals
  const auto pairAt = [&](const glm::vec3* track, const glm::vec3& value, std::int32_t i0, glm::vec3& a,
                          glm::vec3& step) {
    if (track) {
      a = track[i0];
      step = track[std::min(i0 + 1, m_frameCount - 1)] - a;
    } else {
      a = value;
      step = glm::vec3(0.0f);
    }
  };
  for (std::int32_t i0 = 0; i0 < planFrames; ++i0) {
    slots.clear();
    constants.clear();
    std::vector<std::uint32_t> refs(joints, 0);
    for (std::size_t j = 0; j < joints; ++j) {
      const int joint = static_cast<int>(j);
      const std::uint8_t flags = m_flags[j];
      std::int32_t rotation = m_staticPair[j];
      std::int32_t local = -1; // frozen in a cluster: its key's local matrix
      bool sampled = (flags & (kTranslationAnimated | kScaleAnimated)) != 0;
      bool window = false;
      if (flags & kRotationAnimated) {
        const std::span<const Segment> list = segments(joint);
        while (cursor[j] + 1 < list.size() && list[cursor[j] + 1].first <= i0)
          ++cursor[j];
        const Segment& segment = list[cursor[j]];
        rotation = segment.base + segment.step * i0;
        window = blendFrames > 0 && segment.previous >= 0 &&
                 clusters(joint)[static_cast<std::size_t>(segment.previous)].last + blendFrames > i0;
        if (segment.cluster >= 0)
          local = segment.local;
        sampled = sampled || window || segment.cluster < 0;
      }
      if (!sampled) {
        if (local >= 0) {
          constants.emplace_back(j, local);
        } else {
          refs[j] = (kRefStatic << kRefShift) | laneOffset(static_cast<std::uint32_t>(j));
        }
        continue;
      }
      Slot slot{j, m_rotations[static_cast<std::size_t>(rotation)],
                m_rotations[static_cast<std::size_t>(rotation) + 1]};
      if (window) {
        slot.a = composedRotation(joint, i0, blendFrames);
        slot.b = composedRotation(joint, i0 + 1, blendFrames);
        if (glm::dot(slot.a, slot.b) < 0.0f)
          slot.b = -slot.b;
      }
      refs[j] = (kRefSlot << kRefShift) | laneOffset(static_cast<std::uint32_t>(slots.size()));
      slots.push_back(slot);
    }
    const std::size_t slotBlocks = (slots.size() + kLanes - 1) / kLanes;
    const std::size_t constantsAt = slotsAt + slotBlocks * arrays * kLanes;
    const std::size_t size = constantsAt + (constants.size() + kLanes - 1) / kLanes * kLanes * kLocalArrays;
    const std::size_t begin = m_plans.size();
    m_planBegin[static_cast<std::size_t>(i0)] = static_cast<std::uint32_t>(begin);
    m_plans.resize(begin + (size + 15) / 16 * 16, 0.0f);
    float* plan = m_plans.data() + begin;
    plan[0] = planFloat(static_cast<std::uint32_t>(slots.size()));
    plan[1] = planFloat(static_cast<std::uint32_t>(slotBlocks));
    for (std::size_t k = 0; k < constants.size(); ++k) {
      const std::uint32_t at = static_cast<std::uint32_t>(constantsAt) + laneOffset(static_cast<std::uint32_t>(k));
      refs[constants[k].first] = (kRefPlan << kRefShift) | at;
      writeLane(plan + at, m_locals[static_cast<std::size_t>(constants[k].second)]);
    }
    for (std::size_t j = 0; j < joints; ++j)
      plan[kPlanHeader + j] = planFloat(refs[j]);
    for (std::size_t k = 0; k < slotBlocks * kLanes; ++k) {
      float* lane = plan + slotsAt + (k / kLanes) * arrays * kLanes + k % kLanes;
      const auto put = [&](int array, float value) { lane[static_cast<std::size_t>(array) * kLanes] = value; };
      if (k >= slots.size()) { // padding: the identity
        put(kQw, 1.0f);
        if (m_scaled)
          for (const int array : {kSx0, kSy0, kSz0})
            put(array, 1.0f);
        continue;
      }
      const Slot& slot = slots[k];
      const int joint = static_cast<int>(slot.joint);
      const glm::quat d = slot.b - slot.a;
      put(kQx, slot.a.x), put(kQy, slot.a.y), put(kQz, slot.a.z), put(kQw, slot.a.w);
      put(kDx, d.x), put(kDy, d.y), put(kDz, d.z), put(kDw, d.w);
      glm::vec3 a, step;
      pairAt(translationTrack(joint), m_staticTranslation[slot.joint], i0, a, step);
      put(kTx0, a.x), put(kTy0, a.y), put(kTz0, a.z), put(kTdx, step.x), put(kTdy, step.y), put(kTdz, step.z);
      if (m_scaled) {
        pairAt(scaleTrack(joint), m_staticScale[slot.joint], i0, a, step);
        put(kSx0, a.x), put(kSy0, a.y), put(kSz0, a.z), put(kSdx, step.x), put(kSdy, step.y), put(kSdz, step.z);
      }
    }
  }
  m_planBegin[static_cast<std::size_t>(planFrames)] = static_cast<std::uint32_t>(m_plans.size());
  m_maxPlanFloats = 0;
  for (std::size_t f = 0; f < static_cast<std::size_t>(planFrames); ++f)
    m_maxPlanFloats = std::max<std::size_t>(m_maxPlanFloats, m_planBegin[f + 1] - m_planBegin[f]);
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

int LodClip::findSegment(int joint, int i0) const {
  const std::span<const Segment> list = segments(joint);
  const auto found =
      std::upper_bound(list.begin(), list.end(), i0, [](int value, const Segment& s) { return value < s.first; });
  return static_cast<int>(found - list.begin()) - 1;
}

glm::quat LodClip::rotationAt(int joint, double frame, int blendFrames) const {
  if (!(flags(joint) & kRotationAnimated))
    return m_rotations[static_cast<std::size_t>(staticRotationPair(joint))];
  std::int32_t i0 = 0;
  float fraction = 0.0f;
  split(frame, i0, fraction);
  if (!inUnfreezeWindow(joint, i0, blendFrames))
    return composedRotation(joint, frame, 0);
  // inside a window: the nlerp of V(i0) and V(i0 + 1)
  const glm::quat a = composedRotation(joint, i0, blendFrames);
  glm::quat b = composedRotation(joint, i0 + 1, blendFrames);
  if (glm::dot(a, b) < 0.0f)
    b = -b;
  return nlerp(a, b, fraction);
}

glm::quat LodClip::composedRotation(int joint, double frame, int blendFrames) const {
  if (!(flags(joint) & kRotationAnimated))
    return m_rotations[static_cast<std::size_t>(staticRotationPair(joint))];
  std::int32_t i0 = 0;
  float fraction = 0.0f;
  split(frame, i0, fraction);
  const Segment& segment = segments(joint)[static_cast<std::size_t>(findSegment(joint, i0))];
  const std::span<const Cluster> list = clusters(joint);
  const int latest = segment.previous;
  glm::quat s;
  if (segment.cluster >= 0) {
    s = m_rotations[static_cast<std::size_t>(list[static_cast<std::size_t>(segment.cluster)].keyPair)];
  } else {
    const glm::quat* p = &m_rotations[static_cast<std::size_t>(segment.rotation + i0 - segment.first)];
    const bool hold = blendFrames > 0 && latest >= 0 && list[static_cast<std::size_t>(latest)].last == i0;
    s = nlerp(hold ? list[static_cast<std::size_t>(latest)].lastRotation : p[0], p[1], fraction);
  }
  if (blendFrames > 0)
    for (int c = latest; c >= 0 && list[static_cast<std::size_t>(c)].last + blendFrames > i0; --c) {
      const Cluster& cluster = list[static_cast<std::size_t>(c)];
      const double w = std::clamp((frame - cluster.last) / blendFrames, 0.0, 1.0);
      s = scaleOffset(cluster.exitOffset, static_cast<float>(1.0 - w)) * s;
    }
  return s;
}

glm::vec3 LodClip::interpolate(const glm::vec3* track, double frame) const {
  std::int32_t i0 = 0;
  float fraction = 0.0f;
  split(frame, i0, fraction);
  const glm::vec3& a = track[i0];
  const glm::vec3& b = track[std::min(i0 + 1, m_frameCount - 1)];
  return a + (b - a) * fraction;
}

glm::vec3 LodClip::translationAt(int joint, double frame) const {
  const glm::vec3* track = translationTrack(joint);
  return track ? interpolate(track, frame) : staticTranslation(joint);
}

glm::vec3 LodClip::scaleAt(int joint, double frame) const {
  const glm::vec3* track = scaleTrack(joint);
  return track ? interpolate(track, frame) : staticScale(joint);
}

} // namespace mlod
