// The incremental JPC analysis (core/jpc/jpc_analysis.h): every snapshot equals a clustering
// from scratch (simplifyClip) however it was reached, and an edit re-clusters only the
// (level, joint) pairs it reached. On the first 4 s of CMU 01_01 (the bundled sample).

#include "core/jpc/jpc_analysis.h"
#include "io/importer.h"

#include <atomic>
#include <gtest/gtest.h>
#include <stdexcept>

namespace mlod {
namespace {

std::shared_ptr<const Asset> sample() {
  static const std::shared_ptr<const Asset> asset = [] {
    ImportOptions options;
    options.unitScale = 5.6444; // CMU preset
    Result<Asset> imported = importAsset(MLOD_SAMPLE_BVH, options);
    if (!imported)
      throw std::runtime_error(imported.message());
    return std::make_shared<const Asset>(std::move(imported).value());
  }();
  return asset;
}

JpcAnalysisRequest request(const std::vector<double>& thresholds = {0, 5, 50, 100, 300}) {
  JpcAnalysisRequest out;
  out.asset = sample();
  out.clip = 0;
  out.settings.zeroLength = 1e-6 * out.asset->unitScale;
  out.levelThresholds = thresholds;
  return out;
}

std::shared_ptr<const JpcAnalysis> build(const JpcAnalysisRequest& r, std::shared_ptr<const JpcAnalysis> previous = {},
                                         int threads = 0) {
  JpcAnalysisOptions options;
  options.threads = threads;
  Result<std::shared_ptr<const JpcAnalysis>> out = buildJpcAnalysis(r, std::move(previous), options);
  if (!out)
    throw std::runtime_error(out.message());
  return *out;
}

// The snapshot against simplifyClip() of the same request: every level >= 1 (level 0 is the
// original: nothing clustered) has the same clusters and Table 1 figures.
void expectFromScratch(const JpcAnalysis& analysis) {
  const JpcAnalysisRequest& r = request();
  Result<std::vector<JpcLevelResult>> reference =
      simplifyClip(r.asset->skeleton, analysis.clipRef(), analysis.settings, analysis.levelThresholds, 1);
  ASSERT_TRUE(reference) << reference.message();
  ASSERT_EQ(analysis.levelCount(), static_cast<int>(reference->size()));
  EXPECT_EQ(analysis.levels[0].clusterCount, 0);
  for (std::size_t level = 1; level < reference->size(); ++level) {
    const JpcLevelResult& mine = analysis.levels[level];
    const JpcLevelResult& theirs = (*reference)[level];
    EXPECT_EQ(mine.clusters.joints, theirs.clusters.joints) << "level " << level;
    EXPECT_EQ(mine.clusterCount, theirs.clusterCount) << "level " << level;
    EXPECT_DOUBLE_EQ(mine.simplifiedPercent, theirs.simplifiedPercent) << "level " << level;
    EXPECT_DOUBLE_EQ(mine.maxError, theirs.maxError) << "level " << level;
    EXPECT_NEAR(mine.maxJointPositionErrorCm, theirs.maxJointPositionErrorCm, 1e-9) << "level " << level;
  }
}

// Guards the cold build: the same figures as clustering from scratch, on any thread count.
TEST(JpcAnalysis, ColdBuildEqualsSimplifyClip) {
  const auto one = build(request(), {}, 1);
  expectFromScratch(*one);
  EXPECT_EQ(one->clusteredPairs, 4 * one->prepared->clusterableCount());
  const auto many = build(request(), {}, 4);
  for (int level = 0; level < one->levelCount(); ++level)
    EXPECT_EQ(one->levels[std::size_t(level)].clusters.joints, many->levels[std::size_t(level)].clusters.joints);
}

// Guards the cache key: one joint's threshold at one level re-clusters that pair alone, and
// the result is still what a clustering from scratch gives.
TEST(JpcAnalysis, OneJointThresholdReclustersOnePair) {
  const auto before = build(request());
  JpcAnalysisRequest edited = request();
  edited.settings.joints["LeftUpLeg"].thresholds = {std::nullopt, std::nullopt, 12.5};
  EXPECT_FALSE(before->answers(edited));
  const auto after = build(edited, before);
  EXPECT_EQ(after->clusteredPairs, 1);
  expectFromScratch(*after);
  // Levels the edit did not reach keep their measured figures (the same objects' values).
  EXPECT_EQ(after->levels[3].clusters.joints, before->levels[3].clusters.joints);
}

// Guards alpha: a joint's alpha changes its error track, so every level of that joint (and
// nothing else) clusters again.
TEST(JpcAnalysis, JointAlphaReclustersThatJointAtEveryLevel) {
  const auto before = build(request());
  JpcAnalysisRequest edited = request();
  edited.settings.joints["Head"].alpha = 0.5;
  const auto after = build(edited, before);
  EXPECT_EQ(after->clusteredPairs, 4);
  expectFromScratch(*after);
}

// Guards reuse across levels: a level added at an existing threshold clusters nothing;
// moving levels clusters nothing either.
TEST(JpcAnalysis, LevelsAtKnownThresholdsReuseClusterings) {
  const auto before = build(request());
  const auto added = build(request({0, 5, 50, 100, 300, 50}), before);
  EXPECT_EQ(added->clusteredPairs, 0);
  EXPECT_EQ(added->levels[5].clusters.joints, before->levels[2].clusters.joints);
  const auto moved = build(request({0, 50, 5, 100, 300}), before);
  EXPECT_EQ(moved->clusteredPairs, 0);
  expectFromScratch(*moved);
}

// Guards answers(): the same request needs no job; another asset or clip reuses nothing.
TEST(JpcAnalysis, AnswersTheSameRequestOnly) {
  const auto analysis = build(request());
  EXPECT_TRUE(analysis->answers(request()));
  JpcAnalysisRequest mode = request();
  mode.settings.mode = JpcMode::Optimal;
  EXPECT_FALSE(analysis->answers(mode));
  EXPECT_FALSE(analysis->answers(request({0, 5})));
  auto other = std::make_shared<const Asset>(*sample()); // equal content, another asset
  JpcAnalysisRequest elsewhere = request();
  elsewhere.asset = other;
  EXPECT_FALSE(analysis->answers(elsewhere));
  EXPECT_EQ(build(elsewhere, analysis)->clusteredPairs, analysis->clusteredPairs);
}

// Guards cancel and bad input: a raised flag ends the build with kJpcAnalysisCancelled; a
// bad threshold is an error naming the level.
TEST(JpcAnalysis, CancelAndBadThresholdsAreErrors) {
  std::atomic<bool> cancel{true};
  JpcAnalysisOptions options;
  options.cancel = &cancel;
  Result<std::shared_ptr<const JpcAnalysis>> cancelled = buildJpcAnalysis(request(), {}, options);
  ASSERT_FALSE(cancelled);
  EXPECT_EQ(cancelled.message(), kJpcAnalysisCancelled);
  Result<std::shared_ptr<const JpcAnalysis>> bad = buildJpcAnalysis(request({0, 5, -1}), {});
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.message().find("level 2"), std::string::npos) << bad.message();
}

// Guards progress: every clustered pair and every level is reported once, ending at total.
TEST(JpcAnalysis, ProgressCountsEveryStep) {
  std::atomic<int> calls{0}, last{0}, total{0};
  JpcAnalysisOptions options;
  options.threads = 1;
  options.progress = [&](int done, int all) {
    ++calls;
    last = done;
    total = all;
  };
  Result<std::shared_ptr<const JpcAnalysis>> out = buildJpcAnalysis(request(), {}, options);
  ASSERT_TRUE(out);
  EXPECT_EQ(total.load(), (*out)->clusteredPairs + 5);
  EXPECT_EQ(calls.load(), total.load());
  EXPECT_EQ(last.load(), total.load());
}

} // namespace
} // namespace mlod
