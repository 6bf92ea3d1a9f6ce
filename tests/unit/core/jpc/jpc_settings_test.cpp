// Invalid JPC settings are rejected with a message that names the problem; valid edge
// cases (alpha 0, threshold 0, huge thresholds) are accepted.

#include "core/jpc/jpc.h"
#include "core/jpc/jpc_report.h"
#include "core/jpc/simplified_motion.h"
#include "unit/core/jpc/fixtures.h"

#include <cmath>
#include <gtest/gtest.h>
#include <limits>
#include <nlohmann/json.hpp>

namespace mlod {
namespace {

using test::axisAngle;

struct Chain {
  Skeleton skeleton = test::makeChain(3, 10.0f);
  Clip clip = test::chainClip(skeleton, 20, [](int t) { return axisAngle(t < 10 ? 0.0f : 20.0f, {0, 0, 1}); });
};

std::string failure(const Chain& chain, const JpcSettings& settings, std::vector<double> thresholds = {5.0}) {
  Result<std::vector<JpcLevelResult>> result = simplifyClip(chain.skeleton, chain.clip, settings, thresholds);
  return result ? std::string() : result.message();
}

// Guards each rule of JpcSettings::validate() and of the level thresholds, one at a time.
TEST(JpcSettings, InvalidSettingsAreRejectedWithAMessage) {
  const Chain chain;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(failure(chain, {}), "");

  EXPECT_NE(failure(chain, {}, {-1.0}).find("threshold is -1"), std::string::npos) << failure(chain, {}, {-1.0});
  EXPECT_NE(failure(chain, {}, {nan}).find("NaN"), std::string::npos);
  EXPECT_NE(failure(chain, {}, {inf}).find("finite"), std::string::npos);
  EXPECT_NE(failure(chain, {}, {5.0, -2.0}).find("threshold 2"), std::string::npos) << failure(chain, {}, {5.0, -2.0});

  JpcSettings settings;
  settings.alpha = -5.0;
  EXPECT_NE(failure(chain, settings).find("alpha is -5"), std::string::npos) << failure(chain, settings);
  settings.alpha = nan;
  EXPECT_NE(failure(chain, settings).find("alpha is NaN"), std::string::npos) << failure(chain, settings);

  settings = {};
  settings.joints["nosuchjoint"].locked = true;
  EXPECT_NE(failure(chain, settings).find("no joint is named 'nosuchjoint'"), std::string::npos)
      << failure(chain, settings);

  settings = {};
  settings.joints["j1"].alpha = -1.0;
  EXPECT_NE(failure(chain, settings).find("alpha of joint 'j1'"), std::string::npos) << failure(chain, settings);
  settings = {};
  settings.joints["j1"].thresholds = {std::nullopt, nan};
  EXPECT_NE(failure(chain, settings).find("threshold of joint 'j1' at level 1 is NaN"), std::string::npos)
      << failure(chain, settings);
  settings = {};
  settings.joints["j1"].thresholds = {-3.0};
  EXPECT_NE(failure(chain, settings).find("threshold of joint 'j1' at level 0 is -3"), std::string::npos)
      << failure(chain, settings);
  settings = {};
  settings.zeroLength = -1.0;
  EXPECT_NE(failure(chain, settings).find("zero-length"), std::string::npos) << failure(chain, settings);
}

// Guards the clip checks: a clip that does not match its skeleton is an Error, not a crash.
TEST(JpcSettings, MismatchedClipIsRejected) {
  Chain chain;
  chain.clip.rotations.pop_back();
  EXPECT_FALSE(failure(chain, {}).empty());
  Chain nanClip;
  nanClip.clip.rotations[3] = glm::quat(std::nanf(""), 0, 0, 0);
  EXPECT_NE(failure(nanClip, {}).find("non-finite rotation"), std::string::npos) << failure(nanClip, {});
}

// Guards the work limits (issue 29, item 3: a 786,645-frame 3DS ran past 1,200 s): a clip
// one frame past kMaxJpcFrames, or past kMaxJpcJointFrames in rotating joints, is refused
// before any clustering with the limit named; at the limits it is taken, and locked
// joints do not count.
TEST(JpcSettings, WorkLimitsAreRefusedBeforeClustering) {
  const Skeleton chain = test::makeChain(3, 10.0f);
  const auto prepare = [&](int frames, const JpcSettings& settings = {}) {
    const Clip clip = test::chainClip(chain, frames, [](int t) { return axisAngle(t % 7 * 0.01f, {0, 0, 1}); });
    Result<JpcClip> prepared = JpcClip::prepare(chain, clip, settings, JpcTracks::OnDemand);
    return prepared ? std::string() : prepared.message();
  };
  const std::string tooLong = prepare(kMaxJpcFrames + 1);
  EXPECT_NE(tooLong.find(std::to_string(kMaxJpcFrames + 1) + " frames are more than joint posture clustering takes"),
            std::string::npos)
      << tooLong;
  EXPECT_NE(tooLong.find("at most " + std::to_string(kMaxJpcFrames) + " frames per clip"), std::string::npos) << tooLong;
  EXPECT_EQ(prepare(kMaxJpcFrames), "");

  // Many rotating joints: the joint-frames limit.
  Skeleton wide = test::makeChain(3, 10.0f);
  const int frames = 20000;
  const int joints = static_cast<int>(kMaxJpcJointFrames / frames) + 1; // one joint too many
  while (wide.jointCount() < joints) {
    Joint joint = wide.joints.back();
    joint.name = "j" + std::to_string(wide.jointCount());
    joint.parent = wide.jointCount() - 1;
    wide.joints.push_back(joint);
  }
  Clip clip = Clip::restPose(wide, frames, 30.0);
  std::fill(clip.hasRotation.begin(), clip.hasRotation.end(), std::uint8_t{1});
  Result<JpcClip> prepared = JpcClip::prepare(wide, clip, {}, JpcTracks::OnDemand);
  ASSERT_FALSE(prepared);
  EXPECT_NE(prepared.message().find(std::to_string(static_cast<std::int64_t>(joints) * frames) +
                                    " rotating joint-frames are more than joint posture clustering takes (at most " +
                                    std::to_string(kMaxJpcJointFrames) + " per clip)"),
            std::string::npos)
      << prepared.message();
  JpcSettings lockOne;
  lockOne.joints["j1"].locked = true;
  EXPECT_TRUE(JpcClip::prepare(wide, clip, lockOne, JpcTracks::OnDemand)) << "a locked joint is not clustered";
}

// Valid edge cases: alpha 0, T 0, one frame, a threshold beyond every error.
TEST(JpcSettings, EdgeCasesWork) {
  Chain chain;
  JpcSettings settings;
  settings.alpha = 0.0;
  EXPECT_EQ(failure(chain, settings, {0.0, 1e9}), "");
  Chain one;
  one.clip = test::chainClip(one.skeleton, 1, [](int) { return glm::quat(1, 0, 0, 0); });
  Result<std::vector<JpcLevelResult>> result = simplifyClip(one.skeleton, one.clip, {}, std::vector<double>{5.0});
  ASSERT_TRUE(result) << result.message();
  EXPECT_EQ(result->front().clusterCount, 0);
  EXPECT_EQ(result->front().simplifiedPercent, 0.0);
}

// Guards M'(t) and the joint-position error on the chain, by hand: j1 holds 0 degrees for
// frames 0-9 and 20 for 10-19. Forcing one cluster [8, 12] keyed at 8 moves j2 (10 cm
// from j1) through 20 degrees on frames 10-12: 2 x 10 x sin(10 degrees) = 3.473 cm.
TEST(JpcSettings, SimplifiedMotionAndPositionError) {
  const Chain chain;
  ClusterSet clusters;
  clusters.frameCount = 20;
  clusters.joints.resize(3);
  clusters.joints[1] = {{8, 12, 8}};
  ASSERT_FALSE(clusters.validate());
  const Clip simplified = simplifiedClip(chain.clip, clusters);
  for (int t = 0; t < 20; ++t) {
    const bool held = t >= 8 && t <= 12;
    EXPECT_EQ(simplified.rotation(1, t), held ? chain.clip.rotation(1, 8) : chain.clip.rotation(1, t)) << t;
    EXPECT_EQ(simplified.rotation(0, t), chain.clip.rotation(0, t));
  }
  const PositionError error = jointPositionError(chain.skeleton, chain.clip, clusters);
  const double expected = 2.0 * 10.0 * std::sin(glm::radians(10.0));
  EXPECT_NEAR(error.maxCm, expected, 1e-4);
  EXPECT_NEAR(error.meanCm, 3.0 * expected / (20.0 * 3.0), 1e-5); // 3 frames of one joint in 60 joint-frames
  EXPECT_EQ(clusters.clusterAt(1, 7), -1);
  EXPECT_EQ(clusters.clusterAt(1, 8), 0);
  EXPECT_EQ(clusters.clusterAt(1, 12), 0);
  EXPECT_EQ(clusters.clusterAt(1, 13), -1);
}

// Guards ClusterSet::validate(): each rule in turn.
TEST(JpcSettings, ClusterSetValidation) {
  ClusterSet set;
  set.frameCount = 10;
  set.joints = {{{0, 2, 1}, {3, 9, 9}}};
  EXPECT_FALSE(set.validate());
  set.joints = {{{0, 1, 1}}};
  EXPECT_TRUE(set.validate()); // 2 frames
  set.joints = {{{0, 4, 5}}};
  EXPECT_TRUE(set.validate()); // key outside
  set.joints = {{{0, 4, 2}, {4, 8, 5}}};
  EXPECT_TRUE(set.validate()); // overlap
  set.joints = {{{5, 8, 5}, {0, 3, 1}}};
  EXPECT_TRUE(set.validate()); // unsorted
  set.joints = {{{7, 10, 8}}};
  EXPECT_TRUE(set.validate()); // past the end
}

// Guards the JSON contract of docs/architecture.md section 6: the key names, exactly.
TEST(JpcSettings, ReportJsonKeys) {
  const Chain chain;
  Result<std::vector<JpcLevelResult>> levels =
      simplifyClip(chain.skeleton, chain.clip, {}, std::vector<double>{5.0, 300.0});
  ASSERT_TRUE(levels);
  JpcReport report;
  report.file = "chain.bvh";
  report.clip = "chain";
  report.frames = 20;
  report.fps = 30.0;
  report.jointNames = {"j0", "j1", "j2"};
  report.levels = std::move(levels).value();
  const nlohmann::json doc = nlohmann::json::parse(jpcReportJson(report));
  std::vector<std::string> keys;
  for (const auto& item : doc.items())
    keys.push_back(item.key());
  EXPECT_EQ(keys, (std::vector<std::string>{"alpha", "clip", "file", "fps", "frames", "mode", "seconds", "thresholds",
                                            "unit_scale"}));
  ASSERT_EQ(doc["thresholds"].size(), 2u);
  keys.clear();
  for (const auto& item : doc["thresholds"][0].items())
    keys.push_back(item.key());
  EXPECT_EQ(keys, (std::vector<std::string>{"clusters", "joints", "max_error", "max_joint_position_error_cm",
                                            "mean_joint_position_error_cm", "simplified_joint_percent", "threshold"}));
  ASSERT_EQ(doc["thresholds"][0]["joints"].size(), 2u); // j2 has no rotation channel
  keys.clear();
  for (const auto& item : doc["thresholds"][0]["joints"][1].items())
    keys.push_back(item.key());
  EXPECT_EQ(keys, (std::vector<std::string>{"clusters", "max_error", "name", "simplified_percent"}));
  EXPECT_EQ(doc["thresholds"][0]["joints"][1]["name"], "j1");
  EXPECT_EQ(doc["thresholds"][0]["joints"][1]["simplified_percent"], 100.0); // two holds
  EXPECT_EQ(doc["mode"], "greedy");
}

} // namespace
} // namespace mlod
