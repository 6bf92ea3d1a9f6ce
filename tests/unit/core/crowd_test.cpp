// The crowd the studio previews (core/crowd/crowd.h): placement, time offsets, the LOD
// set's switches as the runtime's selection wants them, per-agent levels with hysteresis,
// and the per-frame figures, on BCN_Epileptic and on synthetic skeletons.

#include "core/crowd/crowd.h"
#include "core/lod_clip_builder.h"
#include "fixtures.h"
#include "mesh_lod_fixtures.h"

#include <gtest/gtest.h>

#include <cstring>
#include <memory>

#include <glm/gtc/quaternion.hpp>

#include <numeric>
#include <set>

namespace mlod {
namespace {

// A LodSet with levels switching at `distances` (cm; level 0 the original).
LodSet setWithDistances(std::vector<double> distances, std::vector<double> thresholds = {}) {
  LodSet set;
  LodLevel original;
  original.name = "LOD0";
  set.levels.push_back(original);
  for (std::size_t i = 0; i < distances.size(); ++i) {
    LodLevel level;
    level.name = "LOD" + std::to_string(i + 1);
    level.motionThreshold = i < thresholds.size() ? thresholds[i] : 50.0 * double(i + 1);
    level.meshRatio = 1.0 / double(i + 2);
    level.switchDistanceCm = distances[i];
    set.levels.push_back(level);
  }
  return set;
}

// A chain of `joints` joints swinging about z, 30 frames.
struct SwingingChain {
  Skeleton skeleton;
  Clip clip;
};
SwingingChain swingingChain(int joints) {
  SwingingChain out;
  out.skeleton = test::makeChain(joints, 5.0f);
  out.clip = Clip::restPose(out.skeleton, 30, 30.0);
  out.clip.name = "swing";
  for (int j = 0; j < joints; ++j) {
    out.clip.hasRotation[std::size_t(j)] = 1;
    for (int f = 0; f < 30; ++f)
      out.clip.rotations[out.clip.index(j, f)] = glm::angleAxis(0.02f * float(f) * float(j % 3), glm::vec3(0, 0, 1));
  }
  return out;
}

TEST(CrowdLayout, GridIsCentredAndSpaced) {
  CrowdLayout layout;
  layout.agents = 10; // 4 columns, 3 rows
  layout.spacingCm = 100.0f;
  const std::vector<CrowdAgent> agents = layoutCrowd(layout, 2.0);
  ASSERT_EQ(agents.size(), 10u);
  EXPECT_FLOAT_EQ(agents[0].position.x, -150.0f);
  EXPECT_FLOAT_EQ(agents[0].position.z, -150.0f);
  EXPECT_FLOAT_EQ(agents[3].position.x, 150.0f);
  EXPECT_FLOAT_EQ(agents[4].position.z, -50.0f);
  std::set<std::pair<float, float>> spots;
  for (const CrowdAgent& agent : agents) {
    EXPECT_EQ(agent.position.y, 0.0f);
    EXPECT_GE(agent.timeOffset, 0.0);
    EXPECT_LT(agent.timeOffset, 2.0);
    spots.insert({agent.position.x, agent.position.z});
  }
  EXPECT_EQ(spots.size(), 10u); // nobody stands on anybody
}

TEST(CrowdLayout, ScatteredIsDeterministicAndInsideTheSquare) {
  CrowdLayout layout;
  layout.kind = CrowdLayout::Kind::Scattered;
  layout.agents = 500;
  layout.spacingCm = 100.0f;
  const std::vector<CrowdAgent> a = layoutCrowd(layout, 1.0), b = layoutCrowd(layout, 1.0);
  ASSERT_EQ(a.size(), 500u);
  const float half = 0.5f * 100.0f * 22.0f; // ceil(sqrt(500)) = 23 columns
  std::set<double> offsets;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].position, b[i].position);
    EXPECT_LE(std::abs(a[i].position.x), half);
    EXPECT_LE(std::abs(a[i].position.z), half);
    offsets.insert(a[i].timeOffset);
  }
  EXPECT_GT(offsets.size(), 400u); // each its own offset
  layout.seed = 2;
  EXPECT_NE(layoutCrowd(layout, 1.0)[0].position, a[0].position);
}

TEST(CrowdLayout, ClampsTheAgentCount) {
  CrowdLayout layout;
  layout.agents = 0;
  EXPECT_EQ(layoutCrowd(layout, 1.0).size(), 1u);
  layout.agents = kMaxCrowdAgents + 5;
  EXPECT_EQ(layoutCrowd(layout, 1.0).size(), std::size_t(kMaxCrowdAgents));
  layout.randomOffsets = false;
  layout.agents = 3;
  for (const CrowdAgent& agent : layoutCrowd(layout, 1.0))
    EXPECT_EQ(agent.timeOffset, 0.0);
}

TEST(CrowdSwitches, StrictlyAscendingDistances) {
  const LodSwitches s = lodSwitchesByDistance(setWithDistances({500, 1000, 2000}));
  EXPECT_EQ(s.levels, (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(s.boundaries, (std::vector<float>{500, 1000, 2000}));
}

TEST(CrowdSwitches, LevelsThatNeverShowAreLeftOut) {
  // The default LOD set has no distances: everything switches in at 0, the last level wins.
  LodSwitches s = lodSwitchesByDistance(setWithDistances({0, 0, 0}));
  EXPECT_EQ(s.levels, (std::vector<int>{3}));
  EXPECT_TRUE(s.boundaries.empty());
  // Level 2 switches in where level 3 does: level 3 takes over there.
  s = lodSwitchesByDistance(setWithDistances({500, 1000, 1000}));
  EXPECT_EQ(s.levels, (std::vector<int>{0, 1, 3}));
  EXPECT_EQ(s.boundaries, (std::vector<float>{500, 1000}));
  // Level 1 at 0: level 0 never shows.
  s = lodSwitchesByDistance(setWithDistances({0, 800}));
  EXPECT_EQ(s.levels, (std::vector<int>{1, 2}));
  EXPECT_EQ(s.boundaries, (std::vector<float>{800}));
}

TEST(CrowdSwitches, ScreenSizesDescend) {
  LodSet set = setWithDistances({500, 1000, 2000});
  set.levels[1].screenSizePixels = 300;
  set.levels[2].screenSizePixels = 150;
  set.levels[3].screenSizePixels = 0; // never small enough
  const LodSwitches s = lodSwitchesByScreenSize(set);
  EXPECT_EQ(s.levels, (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(s.boundaries, (std::vector<float>{300, 150}));
}

// The comparison's spread pairs each repetition's configurations (they ran one after
// another, under the same load): a busy repetition slows all four and leaves its ratio
// alone, where a ratio of medians from different repetitions would mix loads.
TEST(CrowdComparisonSpread, PairsTheRepetitions) {
  CrowdComparison comparison;
  comparison.configurations[0].repetitionFrameMs = {10.0, 40.0, 12.0, 11.0, 10.0};
  comparison.configurations[3].repetitionFrameMs = {5.0, 20.0, 4.0, 5.5, 4.0};
  const CrowdComparison::Spread speedup = comparison.speedupSpread(3);
  EXPECT_EQ(speedup.samples, 5);
  EXPECT_DOUBLE_EQ(speedup.median, 2.0); // ratios 2, 2, 3, 2, 2.5
  EXPECT_DOUBLE_EQ(speedup.min, 2.0);
  EXPECT_DOUBLE_EQ(speedup.max, 3.0);
  const CrowdComparison::Spread none = comparison.frameMsSpread(0);
  EXPECT_DOUBLE_EQ(none.median, 11.0);
  EXPECT_DOUBLE_EQ(none.min, 10.0);
  EXPECT_DOUBLE_EQ(none.max, 40.0);
  EXPECT_DOUBLE_EQ(comparison.speedupSpread(0).median, 1.0);
  // an even count: the mean of the middle two; nothing measured: zeros
  comparison.configurations[1].repetitionFrameMs = {10.0, 20.0, 12.0, 44.0};
  EXPECT_DOUBLE_EQ(comparison.frameMsSpread(1).median, 16.0);
  EXPECT_EQ(comparison.frameMsSpread(2).samples, 0);
  EXPECT_EQ(comparison.speedupSpread(2).median, 0.0);
}

TEST(BoneCapsules, OneCapsulePerBoneBoundToItsParent) {
  const Skeleton chain = test::makeChain(4, 10.0f);
  const SkinnedMesh mesh = boneCapsuleMesh(chain, 1.0f);
  EXPECT_FALSE(mesh.validate(chain.jointCount())) << mesh.validate(chain.jointCount()).message();
  EXPECT_EQ(mesh.vertexCount(), 3u * 14u);
  EXPECT_EQ(mesh.triangleCount(), 3u * 24u);
  std::set<int> bound;
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    bound.insert(mesh.joints[v].x);
    EXPECT_EQ(mesh.weights[v].x, 1.0f);
    // every vertex lies within the radius of the chain's axis, between its ends
    EXPECT_LE(std::hypot(mesh.positions[v].x, mesh.positions[v].z), 1.0f + 1e-5f);
    EXPECT_GE(mesh.positions[v].y, -1e-5f);
    EXPECT_LE(mesh.positions[v].y, 30.0f + 1e-5f);
  }
  EXPECT_EQ(bound, (std::set<int>{0, 1, 2}));
  // one joint alone: still something to draw
  EXPECT_GT(boneCapsuleMesh(test::makeChain(1), 2.0f).triangleCount(), 0u);
}

TEST(Crowd, LevelsFollowTheDistancesOfTheLodSet) {
  const SwingingChain chain = swingingChain(6);
  const LodSet set = setWithDistances({500, 1000}, {1000, 100000});
  Result<std::vector<CrowdLevel>> levels = buildCrowdLevels(chain.skeleton, nullptr, chain.clip, set);
  ASSERT_TRUE(levels) << levels.message();
  ASSERT_EQ(levels->size(), 3u);
  for (const CrowdLevel& level : *levels) {
    EXPECT_TRUE(level.capsules);
    EXPECT_FALSE(level.mesh.validate(level.skeleton.jointCount()));
    EXPECT_TRUE(level.clip.looping());
  }
  // a huge threshold removes every moving joint but the root
  EXPECT_LT(levels->back().skeleton.jointCount(), chain.skeleton.jointCount());

  Crowd crowd;
  crowd.setLevels(std::move(levels).value());
  crowd.setSwitches(lodSwitchesByDistance(set), lodSwitchesByScreenSize(set));
  std::vector<CrowdAgent> agents(3);
  agents[0].position = {100, 0, 0};  // level 0
  agents[1].position = {700, 0, 0};  // level 1
  agents[2].position = {1500, 0, 0}; // level 2
  crowd.setAgents(agents);
  ASSERT_FALSE(crowd.update(0.2, glm::vec3(0.0f)));
  EXPECT_EQ(crowd.agentLevel(0), 0);
  EXPECT_EQ(crowd.agentLevel(1), 1);
  EXPECT_EQ(crowd.agentLevel(2), 2);
  EXPECT_EQ(crowd.stats().agentsPerLevel, (std::vector<int>{1, 1, 1}));
  for (int l = 0; l < 3; ++l) {
    ASSERT_EQ(crowd.levelAgents(l).size(), 1u);
    EXPECT_EQ(crowd.levelAgents(l)[0], l);
    EXPECT_EQ(crowd.levelPalettes(l).size(), std::size_t(crowd.level(l).skeleton.jointCount()));
  }
  // Hysteresis (10%): agent 1 moved to 480 cm (inside level 0 but within 10% of 500) stays at
  // level 1; at 440 cm it goes back.
  agents[1].position = {480, 0, 0};
  crowd.setAgents(agents); // forgets levels: plain selection gives level 0 ...
  ASSERT_FALSE(crowd.update(0.2, glm::vec3(0.0f)));
  EXPECT_EQ(crowd.agentLevel(1), 0);
  agents[1].position = {700, 0, 0};
  crowd.setAgents(agents);
  ASSERT_FALSE(crowd.update(0.2, glm::vec3(0.0f)));
  EXPECT_EQ(crowd.agentLevel(1), 1);
  // ... while an agent that stays put keeps its level when the camera moves 20 cm closer
  ASSERT_FALSE(crowd.update(0.2, glm::vec3(220.0f, 0.0f, 0.0f))); // 480 cm away now
  EXPECT_EQ(crowd.agentLevel(1), 1);
  ASSERT_FALSE(crowd.update(0.2, glm::vec3(260.0f, 0.0f, 0.0f))); // 440 cm away
  EXPECT_EQ(crowd.agentLevel(1), 0);
}

// Guards the crowd loop the benchmarks drive: skinning every agent's level mesh counts its
// vertices and takes time; threads and model matrices change no palette; model x inverse
// bind is the palette.
TEST(Crowd, SkinningThreadsAndModels) {
  const SwingingChain chain = swingingChain(6);
  const LodSet set = setWithDistances({500, 1000}, {1000, 100000});
  std::vector<CrowdAgent> agents(40);
  for (std::size_t a = 0; a < agents.size(); ++a) {
    agents[a].position = {50.0f * static_cast<float>(a), 0.0f, 0.0f};
    agents[a].timeOffset = 0.01 * static_cast<double>(a);
  }
  const auto run = [&](int threads, bool models) {
    Result<std::vector<CrowdLevel>> levels = buildCrowdLevels(chain.skeleton, nullptr, chain.clip, set);
    EXPECT_TRUE(levels) << levels.message();
    auto crowd = std::make_unique<Crowd>();
    crowd->setLevels(std::move(levels).value());
    crowd->setSwitches(lodSwitchesByDistance(set), lodSwitchesByScreenSize(set));
    crowd->setAgents(agents);
    crowd->setThreads(threads);
    crowd->setSkinning(true);
    crowd->setModels(models);
    for (int frame = 0; frame < 5; ++frame)
      EXPECT_FALSE(crowd->update(frame / 60.0, glm::vec3(0.0f)));
    return crowd;
  };
  const std::unique_ptr<Crowd> one = run(1, false);
  const std::unique_ptr<Crowd> two = run(2, true);
  EXPECT_EQ(two->threads(), 2);
  std::int64_t vertices = 0;
  for (int l = 0; l < one->levelCount(); ++l) {
    vertices += static_cast<std::int64_t>(one->levelAgents(l).size() * one->level(l).mesh.vertexCount());
    const std::span<const glm::mat4> a = one->levelPalettes(l), b = two->levelPalettes(l);
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size_bytes()), 0) << "level " << l;
    EXPECT_TRUE(one->levelModels(l).empty());
    const std::span<const glm::mat4> models = two->levelModels(l);
    ASSERT_EQ(models.size(), b.size());
    const std::size_t joints = one->level(l).inverseBinds.size();
    for (std::size_t i = 0; i < models.size(); ++i) {
      const glm::mat4 product = models[i] * one->level(l).inverseBinds[i % joints];
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
          EXPECT_NEAR(product[c][r], b[i][c][r], 1e-3f);
    }
  }
  EXPECT_GT(vertices, 0);
  EXPECT_EQ(one->stats().verticesSkinned, vertices);
  EXPECT_GT(one->stats().skinMs, 0.0);
}

TEST(Crowd, LevelsByScreenSize) {
  const SwingingChain chain = swingingChain(4);
  LodSet set = setWithDistances({500, 1000, 2000});
  set.levels[1].screenSizePixels = 400;
  set.levels[2].screenSizePixels = 200;
  set.levels[3].screenSizePixels = 100;
  Result<std::vector<CrowdLevel>> levels = buildCrowdLevels(chain.skeleton, nullptr, chain.clip, set);
  ASSERT_TRUE(levels) << levels.message();
  Crowd crowd;
  crowd.setLevels(std::move(levels).value());
  crowd.setSwitches(lodSwitchesByDistance(set), lodSwitchesByScreenSize(set));
  Crowd::Selection selection;
  selection.mode = LodSelectionJob::Mode::ScreenSize;
  selection.boundingRadiusCm = 90.0f;
  crowd.setSelection(selection);
  std::vector<CrowdAgent> agents;
  for (float x : {100.0f, 300.0f, 600.0f, 1200.0f, 2500.0f, 6000.0f}) {
    CrowdAgent agent;
    agent.position = {x, 0, 0};
    agents.push_back(agent);
  }
  crowd.setAgents(agents);
  ASSERT_FALSE(crowd.update(0.0, glm::vec3(0.0f)));
  const float sizes[] = {400, 200, 100};
  std::set<int> seen;
  for (int a = 0; a < crowd.agentCount(); ++a) {
    const float pixels = projectedSizePixels(90.0f, agents[std::size_t(a)].position.x);
    EXPECT_EQ(crowd.agentLevel(a), selectLevelByScreenSize(pixels, sizes)) << "agent " << a << ", " << pixels << " px";
    seen.insert(crowd.agentLevel(a));
  }
  EXPECT_EQ(seen.size(), 4u); // the agents span every level
  // the distances of the same set give other levels: the mode matters
  selection.mode = LodSelectionJob::Mode::Distance;
  crowd.setSelection(selection);
  ASSERT_FALSE(crowd.update(0.0, glm::vec3(0.0f)));
  EXPECT_EQ(crowd.agentLevel(1), 0); // 300 cm: before the first switch distance
}

TEST(Crowd, PalettesAreTheEvaluatorsForEachAgentsTime) {
  const SwingingChain chain = swingingChain(5);
  Result<std::vector<CrowdLevel>> levels = buildCrowdLevels(chain.skeleton, nullptr, chain.clip, setWithDistances({}));
  ASSERT_TRUE(levels) << levels.message();
  Crowd crowd;
  crowd.setLevels(std::move(levels).value());
  crowd.setSwitches(lodSwitchesByDistance(setWithDistances({})), {});
  CrowdLayout layout;
  layout.agents = 7;
  crowd.setAgents(layoutCrowd(layout, crowd.level(0).clip.duration()));
  ASSERT_FALSE(crowd.update(0.3, glm::vec3(0.0f)));
  const CrowdLevel& level = crowd.level(0);
  const std::size_t joints = std::size_t(level.skeleton.jointCount());
  for (int k = 0; k < 7; ++k) {
    const int agent = crowd.levelAgents(0)[std::size_t(k)];
    const double t = 0.3 + crowd.agents()[std::size_t(agent)].timeOffset;
    const double frame = level.clip.framePosition(t);
    // forward kinematics of the clip's rotations at that frame position
    glm::mat4 model(1.0f);
    for (std::size_t j = 0; j < joints; ++j) {
      const glm::mat4 local = glm::translate(glm::mat4(1.0f), level.clip.translationAt(int(j), frame)) *
                              glm::mat4_cast(level.clip.rotationAt(int(j), frame));
      model = j == 0 ? local : model * local;
      const glm::mat4 expected = model * level.inverseBinds[j];
      const glm::mat4& got = crowd.levelPalettes(0)[std::size_t(k) * joints + j];
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
          EXPECT_NEAR(got[c][r], expected[c][r], 1e-4f) << "agent " << agent << " joint " << j;
    }
  }
}

TEST(Crowd, FiguresOnBcnEpileptic) {
  const Asset& bcn = test::bcnEpileptic();
  ASSERT_FALSE(bcn.clips.empty());
  const LodSet set = setWithDistances({400, 800, 1600}, {5, 50, 300});
  Result<std::vector<CrowdLevel>> levels =
      buildCrowdLevels(bcn.skeleton, &bcn.meshes.front(), bcn.clips.front(), set);
  ASSERT_TRUE(levels) << levels.message();
  ASSERT_EQ(levels->size(), 4u);
  EXPECT_FALSE(levels->front().capsules);
  EXPECT_EQ(levels->front().mesh.vertexCount(), bcn.meshes.front().vertexCount());
  EXPECT_EQ(levels->front().skeleton.jointCount(), bcn.skeleton.jointCount());
  for (std::size_t l = 1; l < levels->size(); ++l) { // coarser levels: fewer triangles, no more joints
    EXPECT_LT((*levels)[l].mesh.triangleCount(), (*levels)[l - 1].mesh.triangleCount());
    EXPECT_LE((*levels)[l].skeleton.jointCount(), (*levels)[l - 1].skeleton.jointCount());
  }
  std::vector<int> vertices;
  for (const CrowdLevel& level : *levels)
    vertices.push_back(int(level.mesh.vertexCount()));

  Crowd crowd;
  crowd.setLevels(std::move(levels).value());
  crowd.setSwitches(lodSwitchesByDistance(set), lodSwitchesByScreenSize(set));
  CrowdLayout layout;
  layout.agents = 400;
  layout.spacingCm = 150.0f;
  crowd.setAgents(layoutCrowd(layout, crowd.level(0).clip.duration()));
  const glm::vec3 camera(0.0f, 170.0f, -1700.0f);
  for (int frame = 0; frame < 3; ++frame) {
    ASSERT_FALSE(crowd.update(frame / 30.0, camera));
    const CrowdFrameStats& stats = crowd.stats();
    EXPECT_EQ(std::accumulate(stats.agentsPerLevel.begin(), stats.agentsPerLevel.end(), 0), 400);
    std::int64_t expectedVertices = 0;
    for (std::size_t l = 0; l < stats.agentsPerLevel.size(); ++l) {
      expectedVertices += std::int64_t(stats.agentsPerLevel[l]) * vertices[l];
      EXPECT_GT(stats.agentsPerLevel[l], 0) << "level " << l; // the grid spans every level's distance
    }
    EXPECT_EQ(stats.verticesSkinned, expectedVertices);
    EXPECT_EQ(stats.jointsFullDetail, 400 * crowd.level(0).fullDetailSampled);
    EXPECT_GT(stats.jointsEvaluated, 0);
    EXPECT_LT(stats.jointsEvaluated, stats.jointsFullDetail); // clusters and bone reduction save joints
    EXPECT_GE(stats.poseCpuMs, 0.0);
  }
  // every agent's level is the plain selection of its distance (first frame after a reset)
  crowd.setAgents(crowd.agents());
  ASSERT_FALSE(crowd.update(0.0, camera));
  const LodSwitches switches = lodSwitchesByDistance(set);
  for (int a = 0; a < crowd.agentCount(); ++a) {
    const float distance = glm::length(crowd.agentCentre(a) - camera);
    EXPECT_EQ(crowd.agentLevel(a), switches.levels[std::size_t(selectLevelByDistance(distance, switches.boundaries))]);
  }
  // forced level
  Crowd::Selection forced;
  forced.forcedLevel = 2;
  crowd.setSelection(forced);
  ASSERT_FALSE(crowd.update(0.1, camera));
  EXPECT_EQ(crowd.stats().agentsPerLevel[2], 400);
}

TEST(Crowd, BadInputIsAnError) {
  const SwingingChain chain = swingingChain(3);
  Clip wrong = chain.clip;
  wrong.jointCount = 2;
  EXPECT_FALSE(buildCrowdLevels(chain.skeleton, nullptr, wrong, setWithDistances({100})));
  LodSet bad = setWithDistances({100});
  bad.levels[1].meshRatio = 0.0;
  EXPECT_FALSE(buildCrowdLevels(chain.skeleton, nullptr, chain.clip, bad));
  std::atomic<bool> cancel{true};
  Result<std::vector<CrowdLevel>> cancelled =
      buildCrowdLevels(chain.skeleton, nullptr, chain.clip, setWithDistances({100}), {}, &cancel);
  ASSERT_FALSE(cancelled);
  EXPECT_EQ(cancelled.message(), "cancelled");
  Crowd empty;
  EXPECT_TRUE(empty.update(0.0, glm::vec3(0.0f)));
}

TEST(Crowd, TwoHundredBones) {
  const SwingingChain chain = swingingChain(200);
  Result<CrowdLevel> level = buildOriginalCrowdLevel(chain.skeleton, nullptr, chain.clip);
  ASSERT_TRUE(level) << level.message();
  EXPECT_EQ(level->parents.size(), 200u);
  Crowd crowd;
  std::vector<CrowdLevel> levels;
  levels.push_back(std::move(level).value());
  crowd.setLevels(std::move(levels));
  crowd.setSwitches(lodSwitchesByDistance(setWithDistances({})), {});
  CrowdLayout layout;
  layout.agents = 20;
  crowd.setAgents(layoutCrowd(layout, 1.0));
  ASSERT_FALSE(crowd.update(0.5, glm::vec3(0.0f)));
  EXPECT_EQ(crowd.levelPalettes(0).size(), 20u * 200u);
}

} // namespace
} // namespace mlod
