// LodClip: its layout on a small chain with hand-placed clusters (known answers), the
// unfreeze blend of a cluster's end, the checks of build(), and on real data what a level
// costs in memory.

#include "runtime/lod_clip.h"
#include "runtime/pose_evaluator.h"
#include "unit/runtime/runtime_fixtures.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

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
    // quantized far below these tests' tolerances: they check M' and its blends, not the
    // precision (PoseEvaluator.QuantizationStaysWithinThePrecision does)
    s.precisionCm = 1e-5;
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

// Guards the layout: static channels found; joint 1's rotation cut into regions (frame 0
// alone, then each cluster and the frames after it), one stored entry per cluster and per
// frame outside clusters; frozen exactly for i0 in [first, last - 1] of a cluster.
TEST(LodClip, RegionsCoverTheClip) {
  const Chain chain;
  std::string error;
  const std::optional<LodClip> clip = LodClip::build(chain.source(), &error);
  ASSERT_TRUE(clip) << error;
  EXPECT_EQ(clip->flags(0), LodClip::kTranslationAnimated);
  EXPECT_EQ(clip->flags(1), LodClip::kRotationAnimated);
  EXPECT_EQ(clip->flags(2), 0);
  EXPECT_EQ(clip->clusterCount(), 3);
  EXPECT_EQ(clip->regionBegin(0), clip->regionBegin(1)) << "a joint that never turns has no regions";
  EXPECT_EQ(clip->regionBegin(3) - clip->regionBegin(2), 0u);
  // [0] + frames 1, 2; [3, 7]; [8, 12] + frames 13, 14; [15, 19]; the sentinel
  const std::uint32_t r0 = clip->regionBegin(1);
  ASSERT_EQ(clip->regionBegin(2) - r0, 5u);
  const int expected[5][3] = {{0, 0, 0}, {3, 7, 3}, {8, 12, 4}, {15, 19, 7}, {20, 20, 8}};
  for (std::uint32_t r = 0; r < 5; ++r) {
    const LodClip::Region region = clip->region(r0 + r);
    EXPECT_EQ(region.first, expected[r][0]) << "region " << r;
    EXPECT_EQ(region.entry, static_cast<std::uint32_t>(expected[r][2])) << "region " << r;
    if (r < 4) {
      EXPECT_EQ(clip->lastOf(r0 + r), expected[r][1]) << "region " << r;
    }
  }
  for (int i0 = 0; i0 <= Chain::kFrames - 2; ++i0) {
    const std::uint32_t r = clip->regionOf(1, i0);
    EXPECT_GE(i0, clip->regionFirst(r));
    EXPECT_LT(i0, clip->regionFirst(r + 1));
    const bool inside = (i0 >= 3 && i0 <= 6) || (i0 >= 8 && i0 <= 11) || (i0 >= 15 && i0 <= 18);
    EXPECT_EQ(clip->frozen(1, i0), inside) << "i0 " << i0;
    EXPECT_FALSE(clip->frozen(0, i0)) << "joint 0 translates";
    EXPECT_TRUE(clip->frozen(2, i0)) << "joint 2 never moves";
  }
  const std::vector<LodClip::Cluster> clusters = clip->clusters(1);
  ASSERT_EQ(clusters.size(), 3u);
  EXPECT_EQ(clusters[1].first, 8);
  EXPECT_EQ(clusters[1].last, 12);
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
// turns 24 degrees at frame 12, so D turns -4 degrees; a clip built for N = 4 stores, at
// frames i in (12, 16), nlerp(identity, D, 1 - (i - 12) / 4) * M'(i), and nlerps between
// frames as everywhere (here every angle is linear in the frame position, so the blend is
// too). The windows of [3, 7] and [8, 12] reach into the next cluster, which then freezes
// only the frames after them: [11, 12] and [16, 19].
// Held or sampled (LodClip's header): a cluster whose frozen frames the runtime would hold
// for fewer than kMinHeldEvaluations evaluations is stored frame by frame, showing the same
// key; at a higher evaluation rate the same cluster is held. The chain's cluster [8, 12] is
// 4 frame intervals: at 30 fps and 60 Hz that is 8 evaluations (held), at 30 Hz 4 (sampled).
TEST(LodClip, ShortClustersAreSampledNotHeld) {
  const Chain chain;
  for (const double hz : {60.0, 30.0}) {
    LodClipSource source = chain.source();
    ASSERT_EQ(source.fps, 30.0);
    source.evaluationsPerSecond = hz;
    const std::optional<LodClip> clip = LodClip::build(source);
    ASSERT_TRUE(clip);
    const bool held = 4 * hz / source.fps >= kMinHeldEvaluations;
    EXPECT_EQ(held, hz == 60.0);
    EXPECT_EQ(clip->frozen(1, 9), held) << hz;
    EXPECT_EQ(clip->clusterCount(), 3); // the clusters JPC found, held or not
    for (double f = 8.0; f <= 12.0; f += 0.5) // the key throughout, either way
      EXPECT_LT(angleBetween(clip->rotationAt(1, f), chain.simplified(10)), 0.01f) << hz << " " << f;
  }
}

TEST(LodClip, ClusterEndBlendsOverNFrames) {
  const Chain chain;
  const int n = 4;
  LodClipSource source = chain.source();
  source.blendFrames = n;
  source.evaluationsPerSecond = 1e6; // every frozen span held: the windows' mechanics under test
  const std::optional<LodClip> plain = LodClip::build(chain.source());
  const std::optional<LodClip> clip = LodClip::build(source);
  ASSERT_TRUE(plain && clip);
  EXPECT_EQ(clip->blendFrames(), n);
  EXPECT_EQ(clip->clusterCount(), 3);
  const std::vector<LodClip::Cluster> clusters = clip->clusters(1);
  ASSERT_EQ(clusters.size(), 3u);
  const int frozen[3][2] = {{3, 7}, {11, 12}, {16, 19}};
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(clusters[static_cast<std::size_t>(c)].first, frozen[c][0]) << "cluster " << c;
    EXPECT_EQ(clusters[static_cast<std::size_t>(c)].last, frozen[c][1]) << "cluster " << c;
  }
  for (int i0 = 0; i0 <= Chain::kFrames - 2; ++i0) {
    const bool inside = (i0 >= 3 && i0 <= 6) || i0 == 11 || (i0 >= 16 && i0 <= 18);
    EXPECT_EQ(clip->frozen(1, i0), inside) << "i0 " << i0;
  }
  const auto nlerp = [](const glm::quat& a, const glm::quat& b, float t) { return glm::normalize(a * (1.0f - t) + b * t); };
  const auto angleOf = [](const glm::quat& q) { return 2.0f * glm::degrees(std::atan2(q.z, q.w)); };
  for (double f = 11.0; f < Chain::kFrames - 1; f += 0.125) {
    const int i = static_cast<int>(f);
    const float a = static_cast<float>(f - i);
    glm::quat s = nlerp(chain.simplified(i), chain.simplified(i + 1), a);
    if (i == 12)
      s = nlerp(turn(24.0f), chain.simplified(13), a);
    glm::quat expected = plain->rotationAt(1, f); // M'
    if (f >= 12.0 && f < 16.0) {
      const float u = 1.0f - static_cast<float>(f - 12.0) / n;
      expected = nlerp(glm::quat(1, 0, 0, 0), turn(-4.0f), u) * s;
    }
    EXPECT_NEAR(angleOf(clip->rotationAt(1, f)), angleOf(expected), 1e-3f) << "frame position " << f;
  }
  EXPECT_LT(angleBetween(clip->rotationAt(1, 12.0), turn(20.0f)), 1e-3f) << "at its last frame: the key";
  EXPECT_LT(angleBetween(clip->rotationAt(1, 13.0), turn(23.0f)), 1e-3f) << "3/4 of D left";
  EXPECT_LT(angleBetween(clip->rotationAt(1, 15.0), turn(33.0f)), 1e-3f) << "the next cluster's key, 1/4 of D left";
  // the window of [3, 7] (D = 10 - 14 degrees) reaches into [8, 12] (key 20 degrees)
  EXPECT_LT(angleBetween(clip->rotationAt(1, 8.0), turn(17.0f)), 1e-3f);
  // the last cluster reaches the clip's end: nothing to leave
  EXPECT_LT(angleBetween(clip->rotationAt(1, 19.0), turn(34.0f)), 1e-3f);
}

// Guards regions past 16 bits: a clip of more than 65,535 frames stores its regions in 32
// bits, and both the reference path and the evaluator find the key of a cluster beyond
// frame 65,535 and the original frames between clusters (a joint turning 0.01 degree a
// frame, a 5-frame cluster every 20 frames, keyed at its middle frame).
TEST(LodClip, LongClipsKeepWideRegions) {
  constexpr int kFrames = 70000;
  std::vector<glm::quat> rotations(2 * kFrames, glm::quat(1, 0, 0, 0));
  std::vector<glm::vec3> translations(2 * kFrames, glm::vec3(0, 10, 0));
  std::vector<glm::vec3> scales(2 * kFrames, glm::vec3(1.0f));
  for (int t = 0; t < kFrames; ++t)
    rotations[static_cast<std::size_t>(kFrames + t)] = turn(0.01f * static_cast<float>(t));
  std::vector<LodCluster> clusters;
  for (int first = 10; first + 4 < kFrames; first += 20)
    clusters.push_back(LodCluster{first, first + 4, first + 2});
  const std::vector<std::uint32_t> clusterBegin{0, 0, static_cast<std::uint32_t>(clusters.size())};
  const std::vector<std::int16_t> parents{-1, 0};
  LodClipSource source;
  source.fps = 120.0;
  source.frameCount = kFrames;
  source.jointCount = 2;
  source.rotations = rotations;
  source.translations = translations;
  source.scales = scales;
  source.clusters = clusters;
  source.clusterBegin = clusterBegin;
  source.parents = parents;
  source.evaluationsPerSecond = 1e6; // every cluster held: the wide regions under test
  source.precisionCm = 1e-5; // quantized far below the tolerances below (as Chain)
  std::string error;
  const std::optional<LodClip> clip = LodClip::build(source, &error);
  ASSERT_TRUE(clip) << error;
  EXPECT_FALSE(clip->narrowRegions());
  // frame 69,010 .. 69,014: a cluster keyed at 69,012; 69,015: moving again
  const std::uint32_t r = clip->regionOf(1, 69011);
  EXPECT_EQ(clip->regionFirst(r), 69010);
  EXPECT_EQ(clip->lastOf(r), 69014);
  EXPECT_TRUE(clip->frozen(1, 69011));
  EXPECT_FALSE(clip->frozen(1, 69015));
  EXPECT_LT(angleBetween(clip->rotationAt(1, 69013.5), turn(690.12f)), 1e-3f);
  EXPECT_LT(angleBetween(clip->rotationAt(1, 69016.0), turn(690.16f)), 1e-3f);
  // the evaluator, one character stepping across the cluster: joint 1's palette turns
  // as rotationAt() says
  PoseEvaluatorContext context(1, 2);
  const std::vector<glm::mat4> inverseBinds(2, glm::mat4(1.0f));
  std::vector<glm::mat4> palette(2);
  const LodClip* clips[1] = {&*clip};
  for (double frame = 69005.0; frame < 69020.0; frame += 0.75) {
    const double times[1] = {frame / source.fps};
    PoseEvaluatorJob job;
    job.parents = parents;
    job.inverseBinds = inverseBinds;
    job.clips = clips;
    job.times = times;
    job.context = &context;
    job.out_palette = palette;
    ASSERT_TRUE(job.run());
    const glm::mat3 expected = glm::mat3_cast(glm::normalize(clip->rotationAt(1, clip->framePosition(times[0]))));
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(palette[1][c][k], expected[c][k], 1e-5f) << "frame " << frame;
  }
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
  EXPECT_LT(angleBetween(clip->rotationAt(0, 0.0), turn(30.0f)), 1e-4f);
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
