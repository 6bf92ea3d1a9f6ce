// LodClip: its layout on a small chain with hand-placed clusters (known answers), the
// unfreeze blend of a cluster's end, the checks of build(), and on real data what a level
// costs in memory.

#include "runtime/lod_clip.h"
#include "unit/runtime/runtime_fixtures.h"

#include <gtest/gtest.h>

#include <vector>

namespace mlod {
namespace {

glm::quat turn(float degrees) { return glm::angleAxis(glm::radians(degrees), glm::vec3(0, 0, 1)); }

// Angle between two rotations, degrees (q and -q are the same rotation).
float angleBetween(const glm::quat& a, const glm::quat& b) {
  return glm::degrees(2.0f * std::acos(std::min(1.0f, std::abs(glm::dot(glm::normalize(a), glm::normalize(b))))));
}

// Three joints, 20 frames at 30 fps: joint 0 still (translation animated: it walks along
// x), joint 1 turning 2 degrees a frame about z, joint 2 a still leaf.
struct Chain {
  static constexpr int kFrames = 20;
  std::vector<glm::quat> rotations = std::vector<glm::quat>(3 * kFrames);
  std::vector<glm::vec3> translations = std::vector<glm::vec3>(3 * kFrames);
  std::vector<glm::vec3> scales = std::vector<glm::vec3>(3 * kFrames, glm::vec3(1.0f));
  std::vector<LodCluster> clusters{{3, 7, 5}, {8, 12, 10}, {15, 19, 17}};
  std::vector<std::uint32_t> clusterBegin{0, 0, 3, 3};
  Chain() {
    for (int t = 0; t < kFrames; ++t) {
      rotations[static_cast<std::size_t>(t)] = glm::quat(1, 0, 0, 0);
      rotations[static_cast<std::size_t>(kFrames + t)] = turn(2.0f * static_cast<float>(t));
      rotations[static_cast<std::size_t>(2 * kFrames + t)] = glm::quat(1, 0, 0, 0);
      translations[static_cast<std::size_t>(t)] = glm::vec3(static_cast<float>(t), 0, 0);
      translations[static_cast<std::size_t>(kFrames + t)] = glm::vec3(0, 10, 0);
      translations[static_cast<std::size_t>(2 * kFrames + t)] = glm::vec3(0, 10, 0);
    }
  }
  LodClipSource source() const {
    LodClipSource s;
    s.fps = 30.0;
    s.frameCount = kFrames;
    s.jointCount = 3;
    s.rotations = rotations;
    s.translations = translations;
    s.scales = scales;
    s.clusters = clusters;
    s.clusterBegin = clusterBegin;
    return s;
  }
  // M': joint 1's rotation at frame t
  glm::quat simplified(int t) const {
    for (const LodCluster& c : clusters)
      if (t >= c.first && t <= c.last)
        return rotations[static_cast<std::size_t>(kFrames + c.key)];
    return rotations[static_cast<std::size_t>(kFrames + t)];
  }
};

// Guards the layout: static channels found, joint 1's frames cut into frozen segments
// (one per cluster, i0 in [first, last - 1]) and sampled ones between, covering i0 in
// [0, frames - 2].
TEST(LodClip, SegmentsCoverTheClip) {
  const Chain chain;
  std::string error;
  const std::optional<LodClip> clip = LodClip::build(chain.source(), &error);
  ASSERT_TRUE(clip) << error;
  EXPECT_EQ(clip->flags(0), LodClip::kTranslationAnimated);
  EXPECT_EQ(clip->flags(1), LodClip::kRotationAnimated);
  EXPECT_EQ(clip->flags(2), 0);
  EXPECT_EQ(clip->clusterCount(), 3);
  const std::span<const LodClip::Segment> segments = clip->segments(1);
  // sampled [0,2], frozen [3,6], sampled [7,7], frozen [8,11], sampled [12,14], frozen [15,18]
  ASSERT_EQ(segments.size(), 6u);
  const int expected[6][3] = {{0, 2, -1}, {3, 6, 0}, {7, 7, -1}, {8, 11, 1}, {12, 14, -1}, {15, 18, 2}};
  for (std::size_t s = 0; s < segments.size(); ++s) {
    EXPECT_EQ(segments[s].first, expected[s][0]) << "segment " << s;
    EXPECT_EQ(segments[s].last, expected[s][1]) << "segment " << s;
    EXPECT_EQ(segments[s].cluster, expected[s][2]) << "segment " << s;
  }
  EXPECT_EQ(segments[2].previous, 0) << "the sampled segment after cluster 0 starts at its last frame";
  for (int i0 = 0; i0 <= Chain::kFrames - 2; ++i0) {
    const int s = clip->findSegment(1, i0);
    ASSERT_GE(s, 0);
    EXPECT_GE(i0, segments[static_cast<std::size_t>(s)].first);
    EXPECT_LE(i0, segments[static_cast<std::size_t>(s)].last);
  }
  EXPECT_TRUE(clip->segments(0).empty()) << "a joint that never turns has no segments";
}

// Guards M'(t): at every frame the key inside clusters and the original outside; between
// frames the nlerp of the two; translations lerped.
TEST(LodClip, RotationAtIsSimplifiedMotion) {
  const Chain chain;
  const std::optional<LodClip> clip = LodClip::build(chain.source());
  ASSERT_TRUE(clip);
  for (int t = 0; t < Chain::kFrames; ++t)
    EXPECT_LT(angleBetween(clip->rotationAt(1, t), chain.simplified(t)), 1e-3f) << "frame " << t;
  // half-way from frame 7 (key 5: 10 degrees) to frame 8 (key 10: 20 degrees): 15 degrees
  EXPECT_LT(angleBetween(clip->rotationAt(1, 7.5), turn(15.0f)), 1e-3f);
  EXPECT_NEAR(clip->translationAt(0, 4.25).x, 4.25f, 1e-5f);
  EXPECT_EQ(clip->translationAt(1, 4.25), glm::vec3(0, 10, 0));
}

// Guards the unfreeze blend of a cluster's end (LodClip header), against its definition
// worked out by hand: cluster [8, 12] holds the key at 20 degrees while the joint really
// turns 24 degrees at frame 12, so D turns -4 degrees; for f in [12, 16) the joint shows
// nlerp(identity, D, 1 - (f - 12) / 4) * S(f), where S is M' except that [12, 13) starts
// from the original 24 degrees instead of the key.
TEST(LodClip, ClusterEndBlendsOverNFrames) {
  const Chain chain;
  const std::optional<LodClip> clip = LodClip::build(chain.source());
  ASSERT_TRUE(clip);
  const int n = 4;
  const LodClip::Cluster& cluster = clip->clusters(1)[1];
  EXPECT_NEAR(angleBetween(cluster.exitOffset, glm::quat(1, 0, 0, 0)), 4.0f, 1e-3f);
  EXPECT_LT(angleBetween(cluster.lastRotation, turn(24.0f)), 1e-3f);
  const auto nlerp = [](const glm::quat& a, const glm::quat& b, float t) { return glm::normalize(a * (1.0f - t) + b * t); };
  const auto angleOf = [](const glm::quat& q) { return 2.0f * glm::degrees(std::atan2(q.z, q.w)); };
  for (double f = 11.0; f < Chain::kFrames - 1; f += 0.125) {
    const int i = static_cast<int>(f);
    const float a = static_cast<float>(f - i);
    glm::quat s = nlerp(chain.simplified(i), chain.simplified(i + 1), a);
    if (i == 12)
      s = nlerp(turn(24.0f), chain.simplified(13), a);
    glm::quat expected = clip->rotationAt(1, f); // M'
    if (f >= 12.0 && f < 16.0) {
      const float u = 1.0f - static_cast<float>(f - 12.0) / n;
      expected = nlerp(glm::quat(1, 0, 0, 0), turn(-4.0f), u) * s;
    }
    EXPECT_NEAR(angleOf(clip->rotationAt(1, f, n)), angleOf(expected), 1e-3f) << "frame position " << f;
  }
  EXPECT_LT(angleBetween(clip->rotationAt(1, 12.0, n), turn(20.0f)), 1e-3f) << "at its last frame: the key";
  // the last cluster reaches the clip's end: nothing to leave
  EXPECT_EQ(clip->clusters(1)[2].exitOffset, glm::quat(1, 0, 0, 0));
}

// Guards frame positions: clamped when the clip does not loop; wrapped, with the period
// count, when it does (period: frames - 1).
TEST(LodClip, FramePositions) {
  Chain chain;
  const std::optional<LodClip> once = LodClip::build(chain.source());
  LodClipSource source = chain.source();
  source.looping = true;
  const std::optional<LodClip> looping = LodClip::build(source);
  ASSERT_TRUE(once && looping);
  EXPECT_DOUBLE_EQ(once->duration(), 19.0 / 30.0);
  EXPECT_DOUBLE_EQ(once->framePosition(0.5), 15.0);
  EXPECT_DOUBLE_EQ(once->framePosition(10.0), 19.0);
  std::int64_t loop = -1;
  EXPECT_NEAR(looping->framePosition(1.0, &loop), 30.0 - 19.0, 1e-9);
  EXPECT_EQ(loop, 1);
  EXPECT_NEAR(looping->framePosition(19.5 / 30.0, &loop), 0.5, 1e-9);
  EXPECT_EQ(loop, 1);
  EXPECT_NEAR(looping->framePosition(18.5 / 30.0, &loop), 18.5, 1e-9);
  EXPECT_EQ(loop, 0);
  std::int32_t i0 = -1;
  float fraction = -1.0f;
  once->split(19.0, i0, fraction);
  EXPECT_EQ(i0, 18);
  EXPECT_EQ(fraction, 1.0f);
}

// Guards the valid edge case of a one-frame clip: every joint static.
TEST(LodClip, OneFrameClip) {
  const std::vector<glm::quat> rotations{turn(30.0f)};
  const std::vector<glm::vec3> translations{{1, 2, 3}};
  const std::vector<glm::vec3> scales{{1, 1, 1}};
  LodClipSource source;
  source.frameCount = 1;
  source.jointCount = 1;
  source.rotations = rotations;
  source.translations = translations;
  source.scales = scales;
  const std::optional<LodClip> clip = LodClip::build(source);
  ASSERT_TRUE(clip);
  EXPECT_EQ(clip->flags(0), 0);
  EXPECT_LT(angleBetween(clip->rotationAt(0, 0.0, 4), turn(30.0f)), 1e-4f);
  EXPECT_EQ(clip->duration(), 0.0);
}

// Guards build()'s checks: each bad source in turn is refused with a message.
TEST(LodClip, RejectsBadSources) {
  const Chain chain;
  const auto refused = [](const LodClipSource& source, const char* what) {
    std::string error;
    EXPECT_FALSE(LodClip::build(source, &error)) << what;
    EXPECT_FALSE(error.empty()) << what;
  };
  {
    LodClipSource s = chain.source();
    s.fps = 0.0;
    refused(s, "no frame rate");
  }
  {
    LodClipSource s = chain.source();
    s.frameCount = 0;
    refused(s, "no frames");
  }
  {
    LodClipSource s = chain.source();
    s.rotations = s.rotations.first(10);
    refused(s, "a short track");
  }
  std::vector<glm::quat> nan = chain.rotations;
  nan[5].x = std::nanf("");
  {
    LodClipSource s = chain.source();
    s.rotations = nan;
    refused(s, "a NaN rotation");
  }
  std::vector<glm::quat> longer = chain.rotations;
  longer[5] = glm::quat(2, 0, 0, 0);
  {
    LodClipSource s = chain.source();
    s.rotations = longer;
    refused(s, "a rotation that is not unit");
  }
  const std::vector<std::vector<LodCluster>> badClusters{
      {{3, 4, 3}},             // two frames
      {{3, 7, 8}},             // key outside
      {{3, 7, 5}, {7, 12, 9}}, // overlapping
      {{8, 12, 9}, {3, 7, 5}}, // unsorted
      {{15, 20, 17}},          // past the clip's end
  };
  for (const std::vector<LodCluster>& clusters : badClusters) {
    const std::vector<std::uint32_t> begin{0, 0, static_cast<std::uint32_t>(clusters.size()),
                                           static_cast<std::uint32_t>(clusters.size())};
    LodClipSource s = chain.source();
    s.clusters = clusters;
    s.clusterBegin = begin;
    refused(s, "bad clusters");
  }
  const std::vector<std::uint32_t> shortBegin{0, 3};
  {
    LodClipSource s = chain.source();
    s.clusterBegin = shortBegin;
    refused(s, "clusterBegin of the wrong size");
  }
}

// Guards what a level costs: the rotations of clustered frames are not stored, so the
// E = 300 clip of CMU 01_01 is smaller than full detail.
TEST(LodClip, LevelsStoreLessThanFullDetail) {
  const Asset& asset = test::runtimeAsset("BVH/01_01.bvh");
  const Clip& clip = asset.clips.front();
  Result<LodClip> full = buildLodClip(clip);
  Result<LodClip> coarse = buildLodClip(clip, &test::levelsOf("BVH/01_01.bvh").back().clusters);
  ASSERT_TRUE(full && coarse);
  EXPECT_LT(coarse->byteSize(), full->byteSize());
  RecordProperty("full bytes", static_cast<int>(full->byteSize()));
  RecordProperty("E=300 bytes", static_cast<int>(coarse->byteSize()));
}

} // namespace
} // namespace mlod
