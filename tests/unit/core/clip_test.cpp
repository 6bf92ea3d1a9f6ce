#include "core/clip.h"
#include "fixtures.h"

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include <limits>

namespace mlod {
namespace {

// Guards restPose(): every frame holds the rest pose and no channel is claimed.
TEST(Clip, RestPoseHoldsTheSkeleton) {
  const Skeleton s = test::makeChain(3);
  const Clip clip = Clip::restPose(s, 5, 30.0);
  EXPECT_FALSE(clip.validate(s));
  EXPECT_EQ(clip.rotationChannelCount(), 0);
  EXPECT_EQ(clip.translation(2, 4), glm::vec3(0, 10, 0));
  EXPECT_DOUBLE_EQ(clip.durationSeconds(), 4.0 / 30.0);
}

// Guards the joint-major layout and forward kinematics of a frame.
TEST(Clip, ModelMatricesUseTheFramesRotations) {
  const Skeleton s = test::makeChain(3);
  Clip clip = Clip::restPose(s, 2, 30.0);
  clip.rotations[clip.index(1, 1)] = glm::angleAxis(glm::radians(90.0f), glm::vec3(0, 0, 1));
  std::vector<glm::mat4> models;
  clip.modelMatrices(s, 0, models);
  EXPECT_NEAR(models[2][3].y, 20.0f, 1e-5f);
  clip.modelMatrices(s, 1, models);
  EXPECT_NEAR(models[2][3].x, -10.0f, 1e-5f); // j2 swings from +y to -x about j1
  EXPECT_NEAR(models[2][3].y, 10.0f, 1e-5f);
}

// Guards validate(): each broken rule in turn, with the joint and frame named.
TEST(Clip, ValidateRejectsEachRule) {
  const Skeleton s = test::makeChain(3);
  const auto expectError = [&](const Clip& clip, const std::string& fragment) {
    const Error error = clip.validate(s);
    ASSERT_TRUE(error) << "expected an error containing '" << fragment << "'";
    EXPECT_NE(error.message().find(fragment), std::string::npos) << error.message();
  };
  const Clip good = Clip::restPose(s, 4, 30.0);
  Clip c = good;
  c.name.clear();
  expectError(c, "no name");
  c = good;
  c.fps = 0.0;
  expectError(c, "frame rate");
  c = good;
  c.fps = std::numeric_limits<double>::quiet_NaN();
  expectError(c, "frame rate");
  c = good;
  c.frameCount = 0;
  expectError(c, "no frames");
  c = good;
  c.jointCount = 2;
  expectError(c, "animates 2 joints");
  c = good;
  c.translations.pop_back();
  expectError(c, "wrong length");
  c = good;
  c.hasRotation.pop_back();
  expectError(c, "channel flags");
  c = good;
  c.rotations[c.index(1, 2)].x = std::numeric_limits<float>::quiet_NaN();
  expectError(c, "non-finite rotation at joint 'j1', frame 2");
  c = good;
  c.rotations[c.index(2, 3)] = glm::quat(0.0f, 0.0f, 0.0f, 0.0f);
  expectError(c, "not a unit quaternion at joint 'j2', frame 3");
  c = good;
  c.translations[c.index(0, 0)].z = std::numeric_limits<float>::infinity();
  expectError(c, "non-finite translation");
  c = good;
  c.scales[c.index(0, 1)].z = std::numeric_limits<float>::quiet_NaN();
  expectError(c, "non-finite scale");
}

// Guards the one-frame clip, a valid edge case with zero duration.
TEST(Clip, OneFrameClipIsValid) {
  const Skeleton s = test::makeChain(2);
  const Clip clip = Clip::restPose(s, 1, 120.0);
  EXPECT_FALSE(clip.validate(s));
  EXPECT_EQ(clip.durationSeconds(), 0.0);
}

} // namespace
} // namespace mlod
