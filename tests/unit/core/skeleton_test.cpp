#include "core/skeleton.h"
#include "fixtures.h"

#include <gtest/gtest.h>

#include <limits>

namespace mlod {
namespace {

// Guards the helpers every algorithm walks the hierarchy with.
TEST(Skeleton, FindChildrenLeaves) {
  Skeleton s = test::makeChain(3);
  Joint extra;
  extra.name = "side";
  extra.parent = 0;
  s.joints.push_back(extra);
  EXPECT_EQ(s.find("j2"), 2);
  EXPECT_EQ(s.find("nope"), -1);
  EXPECT_EQ(s.children(0), (std::vector<int>{1, 3}));
  EXPECT_EQ(s.leafCount(), 2);
  EXPECT_FALSE(s.validate());
}

// Guards forward kinematics of the rest pose (cm).
TEST(Skeleton, RestModelMatricesAccumulateOffsets) {
  const Skeleton s = test::makeChain(4, 12.5f);
  const std::vector<glm::mat4> models = s.restModelMatrices();
  ASSERT_EQ(models.size(), 4u);
  EXPECT_FLOAT_EQ(models[3][3].y, 37.5f);
}

// Guards validate(): each broken rule in turn is named.
TEST(Skeleton, ValidateRejectsEachRule) {
  const auto expectError = [](const Skeleton& s, const std::string& fragment) {
    const Error error = s.validate();
    ASSERT_TRUE(error) << "expected an error containing '" << fragment << "'";
    EXPECT_NE(error.message().find(fragment), std::string::npos) << error.message();
  };
  Skeleton s = test::makeChain(3);
  s.joints[1].name.clear();
  expectError(s, "no name");
  s = test::makeChain(3);
  s.joints[2].name = "j1";
  expectError(s, "two joints are named 'j1'");
  s = test::makeChain(3);
  s.joints[0].parent = 1;
  expectError(s, "must be the root");
  s = test::makeChain(3);
  s.joints[1].parent = 2;
  expectError(s, "parents must come before");
  s = test::makeChain(3);
  s.joints[2].parent = -1; // a second root
  expectError(s, "one root");
  s = test::makeChain(3);
  s.joints[1].rest.translation.x = std::numeric_limits<float>::quiet_NaN();
  expectError(s, "non-finite or non-unit rest");
  s = test::makeChain(3);
  s.joints[1].rest.rotation = glm::quat(0.5f, 0.0f, 0.0f, 0.0f);
  expectError(s, "non-finite or non-unit rest");
  s = test::makeChain(3);
  s.joints[1].inverseBind = glm::mat4(0.0f);
  expectError(s, "singular inverse bind");
  s = test::makeChain(3);
  s.joints[1].inverseBind = glm::mat4(std::numeric_limits<float>::infinity());
  expectError(s, "non-finite inverse bind");
  // finite offsets that add up past float's range (../shared/repro/hang_offset_1e38_2frames.bvh:
  // "height: inf cm", then an export that never ended)
  s = test::makeChain(4);
  for (Joint& joint : s.joints)
    joint.rest.translation = glm::vec3(0.0f, 1e38f, 0.0f);
  expectError(s, "joint 3 'j3' lies at a non-finite position in the rest pose");
}

// Guards the valid edge cases: no joints, one joint, zero-length bones (CMU hips).
TEST(Skeleton, ValidEdgeCases) {
  EXPECT_FALSE(Skeleton{}.validate());
  EXPECT_FALSE(test::makeChain(1).validate());
  EXPECT_FALSE(test::makeChain(5, 0.0f).validate());
}

} // namespace
} // namespace mlod
