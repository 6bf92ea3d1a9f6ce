// Clustering on the synthetic 3-joint chain, where clusters and keys are computed by hand.
// j1 swings about z; a step of d degrees costs E = (10 + alpha) d (r = 10 cm).

#include "core/jpc/clustering_table.h"
#include "core/jpc/greedy_clustering.h"
#include "core/jpc/jpc.h"
#include "core/jpc/key_posture.h"
#include "core/jpc/optimal_clustering.h"
#include "unit/core/jpc/fixtures.h"

#include <gtest/gtest.h>

namespace mlod {
namespace {

using test::axisAngle;

std::vector<Cluster> clustersOf(const JointTrack& track, double threshold, JpcMode mode) {
  return clusterJoint(track, threshold, mode).clusters;
}

// A ramp, 1 degree per frame over 10 frames, alpha = 0: E(t, ref) = 10 |t - ref|.
// At T = 20 every forward run is 3 frames (ref .. ref + 2); greedy takes [0,2], [3,5],
// [6,8] with the middle frames as keys (sums 20 against 30 at the ends) and leaves frame 9.
// Optimal centres keys: [0,4] key 2 and [5,9] key 7 cover all 10 frames with 2 clusters.
TEST(JpcClustering, RampGreedyAndOptimal) {
  const Skeleton chain = test::makeChain(3, 10.0f);
  const Clip clip = test::chainClip(chain, 10, [](int t) { return axisAngle(static_cast<float>(t), {0, 0, 1}); });
  const JointTrack track = test::chainTrack(clip, 0.0);
  const ClusteringTable table(track, 20.5, true);
  for (int ref = 0; ref < 10; ++ref) {
    EXPECT_EQ(table.rowEnd(ref), std::min(ref + 2, 9)) << ref;
    EXPECT_EQ(table.rowStart(ref), std::max(ref - 2, 0)) << ref;
  }
  EXPECT_EQ(clustersOf(track, 20.5, JpcMode::Greedy), (std::vector<Cluster>{{0, 2, 1}, {3, 5, 4}, {6, 8, 7}}));
  EXPECT_EQ(clustersOf(track, 20.5, JpcMode::Optimal), (std::vector<Cluster>{{0, 4, 2}, {5, 9, 7}}));
  // Below one step nothing clusters; past 9 steps everything does, keyed in the middle.
  EXPECT_TRUE(clustersOf(track, 9.0, JpcMode::Greedy).empty());
  EXPECT_TRUE(clustersOf(track, 9.0, JpcMode::Optimal).empty());
  // (frames 4 and 5 tie in exact arithmetic: either may win by rounding)
  for (JpcMode mode : {JpcMode::Greedy, JpcMode::Optimal}) {
    const std::vector<Cluster> all = clustersOf(track, 90.5, mode);
    ASSERT_EQ(all.size(), 1u);
    EXPECT_EQ(all[0].first, 0);
    EXPECT_EQ(all[0].last, 9);
    EXPECT_TRUE(all[0].key == 4 || all[0].key == 5) << all[0].key;
  }
}

// A hold: 6 frames at 0 degrees, then 6 at 30 (alpha = 5: the jump costs 450). Each hold
// is one cluster, even at T = 0 (bit-identical postures), keyed at its first frame (all
// sums are 0: the earliest wins).
TEST(JpcClustering, HoldGreedyAndOptimal) {
  const Skeleton chain = test::makeChain(3, 10.0f);
  const Clip clip = test::chainClip(chain, 12, [](int t) { return axisAngle(t < 6 ? 0.0f : 30.0f, {0, 0, 1}); });
  const JointTrack track = test::chainTrack(clip, 5.0);
  for (double threshold : {0.0, 5.0, 449.0}) {
    SCOPED_TRACE(threshold);
    const std::vector<Cluster> expected{{0, 5, 0}, {6, 11, 6}};
    EXPECT_EQ(clustersOf(track, threshold, JpcMode::Greedy), expected);
    EXPECT_EQ(clustersOf(track, threshold, JpcMode::Optimal), expected);
  }
  // Past the jump, one cluster; keys by eq. (7): every row sums 6 x 450, so frame 0.
  EXPECT_EQ(clustersOf(track, 451.0, JpcMode::Greedy), (std::vector<Cluster>{{0, 11, 0}}));
}

// An oscillation, +10 / -10 degrees on alternate frames (alpha = 0): neighbours differ
// by E = 200, every second frame is identical. Below 200, no run reaches 3 frames; at
// 200 the whole clip is one run, and of 9 frames the 5 at +10 sum 4 x 200 = 800 against
// 1000 for the others: key frame 0.
TEST(JpcClustering, OscillationGreedyAndOptimal) {
  const Skeleton chain = test::makeChain(3, 10.0f);
  const Clip clip = test::chainClip(chain, 9, [](int t) { return axisAngle(t % 2 == 0 ? 10.0f : -10.0f, {0, 0, 1}); });
  const JointTrack track = test::chainTrack(clip, 0.0);
  EXPECT_NEAR(track.error(1, 0), 200.0, 1e-3);
  EXPECT_TRUE(clustersOf(track, 199.0, JpcMode::Greedy).empty());
  EXPECT_TRUE(clustersOf(track, 199.0, JpcMode::Optimal).empty());
  EXPECT_EQ(clustersOf(track, 201.0, JpcMode::Greedy), (std::vector<Cluster>{{0, 8, 0}}));
  EXPECT_EQ(clustersOf(track, 201.0, JpcMode::Optimal), (std::vector<Cluster>{{0, 8, 0}}));
  const KeyPosture key = keyPosture(track, {0, 8}, 201.0);
  EXPECT_EQ(key.key, 0);
  EXPECT_NEAR(key.errorSum, 800.0, 1e-2);
  EXPECT_NEAR(key.maxError, 200.0, 1e-3);
}

// Guards the tie rule of STEP 2 (the earliest of equally long ranges) and the cut of
// STEP 5 (a range starting before the chosen one ends just before it).
TEST(JpcClustering, GreedyTiesAndCuts) {
  // Ranges: 0 -> [0,3] (4), 2 -> [2,7] (6), 5 -> [5,10] (6), others short.
  std::vector<int> ends{3, 1, 7, 3, 4, 10, 6, 7, 8, 9, 10};
  // [2,7] wins the tie; 0 is cut to [0,1] (2 frames: dropped); 5 starts inside it
  // (dropped); nothing else reaches 3 frames: one cluster.
  EXPECT_EQ(greedyRanges(ends), (std::vector<FrameRange>{{2, 7}}));
  ends = {4, 1, 2, 3, 4, 9, 6, 7, 8, 9};
  // 0 -> [0,4] and 5 -> [5,9]: equal, earliest first, no overlap: both.
  EXPECT_EQ(greedyRanges(ends), (std::vector<FrameRange>{{0, 4}, {5, 9}}));
}

// Guards the optimal DP against the tempting inexact one that keeps, per range end, only
// the smallest feasible start: that one takes [1,7] (7 frames) for the end 7, while
// [0,2] + [3,7] covers all 8.
TEST(JpcClustering, OptimalIsExactWhereSmallestStartIsNot) {
  // each key k's window [start, end]
  const std::vector<int> starts{0, 0, 0, 1, 1, 5, 5, 5};
  const std::vector<int> ends{2, 2, 2, 7, 7, 7, 7, 7};
  EXPECT_EQ(optimalRanges(starts, ends), (std::vector<FrameRange>{{0, 2}, {3, 7}}));
}

// Guards the whole-clip shortcut: a joint whose largest possible error is within T gets
// one cluster without table work, keyed by eq. (7).
TEST(JpcClustering, WholeClipShortcut) {
  const Skeleton chain = test::makeChain(3, 10.0f);
  const Clip clip = test::chainClip(chain, 7, [](int t) { return axisAngle(static_cast<float>(t * t), {0, 0, 1}); });
  const JointTrack track = test::chainTrack(clip, 5.0);
  const double threshold = 15.0 * 180.0 * 1.01;
  const ClusteringTable table(track, threshold, true);
  EXPECT_TRUE(table.wholeClip());
  EXPECT_EQ(table.evaluations(), 0);
  const JointClustering result = clusterJoint(track, threshold, JpcMode::Greedy);
  ASSERT_EQ(result.clusters.size(), 1u);
  EXPECT_EQ(result.clusters[0].first, 0);
  EXPECT_EQ(result.clusters[0].last, 6);
  // angles 0 1 4 9 16 25 36: the sum of |a - a_k| is least at the median, 9 (frame 3)
  EXPECT_EQ(result.clusters[0].key, 3);
}

// Clips shorter than 3 frames cannot hold a cluster.
TEST(JpcClustering, ShortClips) {
  const Skeleton chain = test::makeChain(3, 10.0f);
  for (int frames : {1, 2}) {
    const Clip clip = test::chainClip(chain, frames, [](int) { return glm::quat(1, 0, 0, 0); });
    const JointTrack track = test::chainTrack(clip, 5.0);
    EXPECT_TRUE(clustersOf(track, 1000.0, JpcMode::Greedy).empty());
    EXPECT_TRUE(clustersOf(track, 1000.0, JpcMode::Optimal).empty());
  }
}

} // namespace
} // namespace mlod
