// What a pixel budget's search keeps between runs (core/lod/lod_budget_cache.h): a run asked
// again computes nothing it computed before, an edit re-clusters only what it changed, and
// the levels and report are always those of a run without the cache (never stale).

#include "core/lod/lod_budget_cache.h"
#include "core/lod/lod_set.h"
#include "unit/core/mesh_lod_fixtures.h"

#include <gtest/gtest.h>

namespace mlod {
namespace {

// Everything a run reports besides its statistics.
void expectSameRun(const LodSet& a, const LodBudgetReport& reportA, const LodSet& b, const LodBudgetReport& reportB) {
  EXPECT_EQ(a, b);
  EXPECT_EQ(reportA.simplifiedPercent, reportB.simplifiedPercent);
  EXPECT_EQ(reportA.dropped, reportB.dropped);
  EXPECT_EQ(reportA.motionShare, reportB.motionShare);
}

struct Generated {
  LodSet set;
  LodBudgetReport report;
};

Generated run(const Asset& asset, double pixels, int levels, const LodBudgetOptions& options) {
  Generated out;
  Result<LodSet> set = LodSet::fromPixelBudget(asset, pixels, levels, options, &out.report);
  EXPECT_TRUE(set) << set.message();
  if (set)
    out.set = std::move(set).value();
  return out;
}

// Guards the reuse (issue 26, item 4: the Budget preview took 5 s each time it was asked):
// the same request again prepares, clusters, bone-reduces and simplifies nothing, and
// another budget and level count on the same character reuse what the first run made.
TEST(LodBudgetCache, ARunAskedAgainComputesNothingItComputedBefore) {
  const Asset& asset = test::bcnEpileptic();
  LodBudgetCache cache;
  LodBudgetOptions options;
  options.cache = &cache;
  const Generated first = run(asset, 1.0, 4, options);
  EXPECT_TRUE(first.report.characterPrepared);
  EXPECT_GT(first.report.jointsClustered, 0);
  EXPECT_GT(first.report.motionsMade, 0);
  EXPECT_GT(first.report.meshesBuilt, 0);
  EXPECT_FALSE(cache.empty());

  const Generated again = run(asset, 1.0, 4, options);
  EXPECT_FALSE(again.report.characterPrepared);
  EXPECT_EQ(again.report.jointsClustered, 0);
  EXPECT_EQ(again.report.motionsMade, 0);
  EXPECT_EQ(again.report.meshesBuilt, 0);
  expectSameRun(again.set, again.report, first.set, first.report);

  // another budget and level count: what it computes is what a run without the cache gives
  for (const auto& [pixels, levels] : {std::pair{2.0, 5}, {0.5, 3}}) {
    const Generated cached = run(asset, pixels, levels, options);
    EXPECT_FALSE(cached.report.characterPrepared);
    LodBudgetOptions alone = options;
    alone.cache = nullptr;
    const Generated fresh = run(asset, pixels, levels, alone);
    expectSameRun(cached.set, cached.report, fresh.set, fresh.report);
    EXPECT_LT(cached.report.jointsClustered, fresh.report.jointsClustered) << pixels << " px, " << levels;
  }
}

// Guards against stale reuse: after a joint edit (its lock, then its alpha) the cached run
// gives what a run without the cache gives on the edited settings, not the levels of
// before, and clusters that joint alone; another clip prepares the character again.
TEST(LodBudgetCache, AnEditIsNeverAnsweredFromTheCache) {
  const Asset& asset = test::bcnEpileptic();
  LodBudgetCache cache;
  LodBudgetOptions options;
  options.cache = &cache;
  const Generated before = run(asset, 1.0, 4, options);
  ASSERT_GE(before.set.levels.size(), 2u);

  // every joint but the root locked: the figures change
  LodBudgetOptions alone = options;
  alone.cache = nullptr;
  for (std::size_t j = 1; j < asset.skeleton.joints.size(); ++j)
    options.jpc.joints[asset.skeleton.joints[j].name].locked = true;
  const Generated locked = run(asset, 1.0, 4, options);
  alone.jpc = options.jpc;
  const Generated lockedFresh = run(asset, 1.0, 4, alone);
  expectSameRun(locked.set, locked.report, lockedFresh.set, lockedFresh.report);
  EXPECT_NE(locked.report.simplifiedPercent, before.report.simplifiedPercent);
  EXPECT_FALSE(locked.report.characterPrepared);
  EXPECT_LE(locked.report.jointsClustered, lockedFresh.report.jointsClustered);
  EXPECT_GT(locked.report.motionsMade, 0) << "the motions depend on every joint";

  // one joint's alpha: that joint is clustered again, the others are kept
  options.jpc.joints.clear();
  const std::string joint = asset.skeleton.joints[1].name;
  options.jpc.joints[joint].alpha = 50.0;
  const Generated alpha = run(asset, 1.0, 4, options);
  alone.jpc = options.jpc;
  const Generated alphaFresh = run(asset, 1.0, 4, alone);
  expectSameRun(alpha.set, alpha.report, alphaFresh.set, alphaFresh.report);
  EXPECT_GT(alpha.report.jointsClustered, 0);
  EXPECT_LT(alpha.report.jointsClustered, alphaFresh.report.jointsClustered) << "only " << joint << " again";

  // another clip (one rotation changed): everything again, the same as without the cache
  std::vector<Clip> clips = {asset.clips.front()};
  clips.front().rotations[clips.front().index(1, 0)] = glm::quat(1.0f, 0.0f, 0.0f, 0.0f);
  options.clips = clips;
  alone.clips = clips;
  const Generated otherClip = run(asset, 1.0, 4, options);
  EXPECT_TRUE(otherClip.report.characterPrepared);
  const Generated otherClipFresh = run(asset, 1.0, 4, alone);
  expectSameRun(otherClip.set, otherClip.report, otherClipFresh.set, otherClipFresh.report);
}

// A cancelled run keeps only what it finished: the next run gives what a fresh one gives.
TEST(LodBudgetCache, ACancelledRunLeavesNothingHalfDone) {
  const Asset& asset = test::bcnEpileptic();
  LodBudgetCache cache;
  LodBudgetOptions options;
  options.cache = &cache;
  for (int stopAt : {2, 4, 6}) {
    int calls = 0;
    options.progress = [&](double) { return ++calls < stopAt; };
    const Result<LodSet> cancelled = LodSet::fromPixelBudget(asset, 1.0, 4, options);
    ASSERT_FALSE(cancelled);
    EXPECT_EQ(cancelled.message(), kLodBudgetCancelled);
  }
  options.progress = {};
  const Generated cached = run(asset, 1.0, 4, options);
  LodBudgetOptions alone;
  const Generated fresh = run(asset, 1.0, 4, alone);
  expectSameRun(cached.set, cached.report, fresh.set, fresh.report);
}

} // namespace
} // namespace mlod
