// The banded table, the greedy and optimal selections and the pruned key search against
// brute-force references on clips of at most 300 frames: same runs, same table entries
// in the band, same clusters, same keys (one scalar kernel serves both sides).

#include "core/jpc/clustering_table.h"
#include "core/jpc/greedy_clustering.h"
#include "core/jpc/jpc.h"
#include "core/jpc/key_posture.h"
#include "core/jpc/optimal_clustering.h"
#include "unit/core/jpc/fixtures.h"
#include "unit/core/jpc/reference.h"

#include <gtest/gtest.h>
#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace mlod {
namespace {

const std::vector<double> kThresholds{0.0, 1.0, 5.0, 20.0, 50.0, 100.0, 300.0, 1000.0};

int covered(const std::vector<FrameRange>& ranges) {
  int frames = 0;
  for (const FrameRange& r : ranges)
    frames += r.length();
  return frames;
}

// Compares everything for one track at every threshold.
void compareWithReference(const JointTrack& track, const std::string& what) {
  const int n = track.frameCount();
  const std::vector<double> table = test::fullTable(track);
  for (double threshold : kThresholds) {
    SCOPED_TRACE(what + " T=" + std::to_string(threshold));
    const ClusteringTable banded(track, threshold, true);
    const std::vector<int> ends = test::referenceRowEnds(table, n, threshold);
    const std::vector<int> starts = test::referenceRowStarts(table, n, threshold);
    ASSERT_EQ(banded.rowEnds(), ends);
    ASSERT_EQ(banded.rowStarts(), starts);
    for (int ref = 0; ref < n; ref += 7)
      for (int t = starts[static_cast<std::size_t>(ref)]; t <= ends[static_cast<std::size_t>(ref)]; ++t)
        ASSERT_EQ(banded.entry(t, ref), table[static_cast<std::size_t>(ref * n + t)]);
    EXPECT_EQ(ClusteringTable(track, threshold, false).rowEnds(), ends); // without starts, the same ends

    // Greedy: the same ranges as the paper's loop, the same keys as the full eq. (7).
    const std::vector<FrameRange> greedy = greedyRanges(ends);
    ASSERT_EQ(greedy, test::referenceGreedyRanges(ends));
    std::vector<Cluster> expected;
    for (const FrameRange& range : greedy) {
      const int key = test::referenceKey(table, n, range, threshold);
      ASSERT_GE(key, 0);
      EXPECT_EQ(keyPosture(track, range, threshold).key, key);
      EXPECT_EQ(keyPosture(track, range, threshold, &banded).key, key);
      expected.push_back({range.first, range.last, key});
    }
    EXPECT_EQ(clusterJoint(track, threshold, JpcMode::Greedy).clusters, expected);

    // Optimal: the reference coverage (frames, then clusters), every range keyed within T.
    const std::vector<FrameRange> optimal = optimalRanges(starts, ends);
    const test::Coverage best = test::referenceOptimalCoverage(table, n, threshold);
    EXPECT_EQ(covered(optimal), best.frames);
    EXPECT_EQ(static_cast<int>(optimal.size()), best.clusters);
    EXPECT_GE(covered(optimal), covered(greedy));
    const JointClustering clustered = clusterJoint(track, threshold, JpcMode::Optimal);
    ASSERT_EQ(clustered.clusters.size(), optimal.size());
    for (std::size_t i = 0; i < optimal.size(); ++i) {
      const Cluster& c = clustered.clusters[i];
      EXPECT_EQ(c.first, optimal[i].first);
      EXPECT_EQ(c.last, optimal[i].last);
      EXPECT_EQ(c.key, test::referenceKey(table, n, optimal[i], threshold));
    }
  }
}

// Real motion: every clusterable joint of the CMU clip, two 300-frame stretches, alpha 0 and 5.
TEST(JpcReference, CmuExcerptsMatchBruteForce) {
  const Asset& asset = test::realAsset("BVH/01_01.bvh");
  const Clip& clip = asset.clips.front();
  const std::vector<JointGeometry> geometry = jointGeometry(asset.skeleton, 1e-6 * asset.unitScale);
  for (int first : {0, 1500}) {
    for (double alpha : {0.0, 5.0}) {
      for (int j = 0; j < clip.jointCount; ++j) {
        if (!clip.hasRotation[static_cast<std::size_t>(j)])
          continue;
        const JointTrack track(geometry[static_cast<std::size_t>(j)], alpha, test::rotationsOf(clip, j, first, 300));
        compareWithReference(track, asset.skeleton.joints[static_cast<std::size_t>(j)].name + " from " +
                                        std::to_string(first) + " alpha " + std::to_string(alpha));
        if (HasFatalFailure())
          return;
      }
    }
  }
}

// The character of the X file: other rig, other frame rate, resampled keys.
TEST(JpcReference, CharacterClipMatchesBruteForce) {
  const Asset& asset = test::realAsset("X/BCN_Epileptic.X");
  ASSERT_FALSE(asset.clips.empty());
  const Clip& clip = asset.clips.front();
  const std::vector<JointGeometry> geometry = jointGeometry(asset.skeleton, 1e-6 * asset.unitScale);
  const int frames = std::min(clip.frameCount, 300);
  for (int j = 0; j < clip.jointCount; ++j) {
    if (!clip.hasRotation[static_cast<std::size_t>(j)])
      continue;
    const JointTrack track(geometry[static_cast<std::size_t>(j)], 5.0, test::rotationsOf(clip, j, 0, frames));
    compareWithReference(track, asset.skeleton.joints[static_cast<std::size_t>(j)].name);
    if (HasFatalFailure())
      return;
  }
}

// Synthetic motion built to stress ties and skips: holds of bit-identical postures, tiny
// noise, jumps and slow drifts.
TEST(JpcReference, SyntheticHoldsNoiseAndJumpsMatchBruteForce) {
  std::mt19937 rng(1234);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  for (int trial = 0; trial < 6; ++trial) {
    const Skeleton chain = test::makeChain(3, 10.0f);
    std::vector<glm::quat> rotations;
    glm::quat current(1, 0, 0, 0);
    while (rotations.size() < 250) {
      const int kind = static_cast<int>(rng() % 4);
      const int length = 1 + static_cast<int>(rng() % 30);
      for (int i = 0; i < length; ++i) {
        if (kind == 1) // drift
          current = glm::normalize(current * test::axisAngle(2.0f, {unit(rng), unit(rng), unit(rng)}));
        else if (kind == 2) // noise
          current = glm::normalize(current * test::axisAngle(0.05f * (trial + 1), {unit(rng), unit(rng), unit(rng)}));
        rotations.push_back(current); // kind 0 and 3: hold
      }
      if (kind == 3) // jump
        current = glm::normalize(current * test::axisAngle(40.0f, {unit(rng), unit(rng), unit(rng)}));
    }
    const Clip clip = test::chainClip(chain, static_cast<int>(rotations.size()),
                                      [&](int t) { return rotations[static_cast<std::size_t>(t)]; });
    for (double alpha : {0.0, 5.0}) {
      compareWithReference(test::chainTrack(clip, alpha), "trial " + std::to_string(trial));
      if (HasFatalFailure())
        return;
    }
  }
}

// Guards the key search on slow motions that stay inside the threshold for thousands of
// frames (issue 29, item 3: a slow turn of 50,000 frames took 41 s, quadratic): the key is
// the full table's, and the search evaluates each frame a few times, not every row (before,
// thousands of rows of a 20,000-frame turn were summed exactly: tens of millions).
TEST(JpcReference, SlowMotionsKeyAsTheFullTableSaysInFewEvaluations) {
  const Skeleton chain = test::makeChain(3, 10.0f);
  const auto turn = [](int frames) {
    return [frames](int t) { return test::axisAngle(0.4f * std::sqrt(static_cast<float>(t) / frames), {0, 0, 1}); };
  };
  const auto wobble = [](int t) {
    const float a = static_cast<float>(t);
    return test::axisAngle(0.3f * std::sin(a * 0.011f), {0, 0, 1}) * test::axisAngle(0.3f * std::sin(a * 0.0071f + 1.0f), {1, 0, 0});
  };
  const int n = 2500;
  for (const auto& [what, rotation] :
       std::vector<std::pair<std::string, std::function<glm::quat(int)>>>{{"turn", turn(n)}, {"wobble", wobble}}) {
    SCOPED_TRACE(what);
    const Clip clip = test::chainClip(chain, n, rotation);
    const JointTrack track = test::chainTrack(clip, 5.0);
    const std::vector<double> table = test::fullTable(track);
    const FrameRange all{0, n - 1};
    const double threshold = 100.0;
    const int key = test::referenceKey(table, n, all, threshold);
    ASSERT_GE(key, 0);
    EXPECT_EQ(keyPosture(track, all, threshold).key, key);
  }
  const int frames = 20000;
  const Clip clip = test::chainClip(chain, frames, turn(frames));
  const KeyPosture key = keyPosture(test::chainTrack(clip, 0.0), {0, frames - 1}, 100.0);
  EXPECT_GE(key.key, 0);
  EXPECT_LT(key.evaluations, 20 * static_cast<std::int64_t>(frames));
}

// A joint that keeps one pose under float noise (BCN_Epileptic's fingers under the mapped CMU
// 01_03: 4,510 frames in one cluster, 715 distinct rotations, not in runs) made the key
// search sum every row exactly: 15 million evaluations, most of the budget preview's time.
// Frames of one posture share their errors, so each row costs one evaluation per posture and
// a repeated posture is not a row of its own; the key is still the full table's.
TEST(JpcReference, RepeatedPosturesKeyAsTheFullTableSaysInFewEvaluations) {
  const Skeleton chain = test::makeChain(3, 10.0f);
  const int n = 1200, postures = 9;
  std::mt19937 random(26);
  std::vector<int> pick(static_cast<std::size_t>(n));
  for (int& p : pick)
    p = static_cast<int>(random() % postures);
  const auto jitter = [&](int t) {
    const float a = 1e-4f * static_cast<float>(pick[static_cast<std::size_t>(t)]);
    return test::axisAngle(0.2f + a, {0, 0, 1}) * test::axisAngle(a, {1, 0, 0});
  };
  const Clip clip = test::chainClip(chain, n, jitter);
  for (double alpha : {0.0, 5.0}) {
    SCOPED_TRACE("alpha " + std::to_string(alpha));
    const JointTrack track = test::chainTrack(clip, alpha);
    const std::vector<double> table = test::fullTable(track);
    const FrameRange all{0, n - 1};
    for (double threshold : {1.0, 5.0}) {
      const int key = test::referenceKey(table, n, all, threshold);
      ASSERT_GE(key, 0);
      const KeyPosture found = keyPosture(track, all, threshold);
      EXPECT_EQ(found.key, key);
      EXPECT_LE(found.evaluations, 40 * static_cast<std::int64_t>(postures) * postures + 20 * n);
    }
  }
}

} // namespace
} // namespace mlod
