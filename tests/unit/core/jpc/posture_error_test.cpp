// The JPC error metric, eqs. (1)-(6) as docs/architecture.md section 4 defines them.

#include "core/jpc/posture_error.h"
#include "unit/core/jpc/fixtures.h"

#include <gtest/gtest.h>
#include <random>

namespace mlod {
namespace {

using test::axisAngle;

glm::dvec3 randomUnit(std::mt19937& rng) {
  std::normal_distribution<double> normal;
  return glm::normalize(glm::dvec3(normal(rng), normal(rng), normal(rng)));
}

glm::dquat randomRotation(std::mt19937& rng) {
  std::normal_distribution<double> normal;
  return glm::normalize(glm::dquat(normal(rng), normal(rng), normal(rng), normal(rng)));
}

// Guards eq. (3)'s form: exactly 0 for identical directions (arccos gives ~1e-6 degrees)
// and exactly symmetric, which T = 0 and the brute-force comparisons rely on.
TEST(JpcError, DirectionAngleIsExactlyZeroAndSymmetric) {
  std::mt19937 rng(7);
  for (int i = 0; i < 10000; ++i) {
    const glm::dvec3 a = randomUnit(rng), b = randomUnit(rng);
    EXPECT_EQ(directionAngleDegrees(a, a), 0.0);
    EXPECT_EQ(directionAngleDegrees(a, b), directionAngleDegrees(b, a));
  }
  EXPECT_NEAR(directionAngleDegrees({1, 0, 0}, {0, 1, 0}), 90.0, 1e-12);
  EXPECT_NEAR(directionAngleDegrees({1, 0, 0}, {-1, 0, 0}), 180.0, 1e-12);
  EXPECT_NEAR(directionAngleDegrees({2, 0, 0}, {1, 1, 0}), 45.0, 1e-12); // lengths do not matter
  // accurate near 0, where arccos(dot) loses half the digits
  const double tiny = 1e-9; // radians
  EXPECT_NEAR(directionAngleDegrees({1, 0, 0}, {std::cos(tiny), std::sin(tiny), 0}), tiny * kDegreesPerRadian, 1e-20);
}

// Guards eq. (6): the shorter rotation angle, the same for q and -q, exactly 0 and
// exactly symmetric.
TEST(JpcError, RotationAngleIsShortestSignFreeExactlyZeroAndSymmetric) {
  std::mt19937 rng(11);
  for (int i = 0; i < 10000; ++i) {
    const glm::dquat a = randomRotation(rng), b = randomRotation(rng);
    EXPECT_EQ(rotationAngleDegrees(a, a), 0.0);
    EXPECT_EQ(rotationAngleDegrees(a, -a), 0.0);
    EXPECT_EQ(rotationAngleDegrees(a, b), rotationAngleDegrees(b, a));
    EXPECT_EQ(rotationAngleDegrees(a, b), rotationAngleDegrees(a, -b));
    EXPECT_LE(rotationAngleDegrees(a, b), 180.0 + 1e-12);
  }
  const glm::dquat identity(1, 0, 0, 0);
  EXPECT_NEAR(rotationAngleDegrees(identity, glm::dquat(glm::angleAxis(glm::radians(90.0), glm::dvec3(1, 0, 0)))), 90.0,
              1e-12);
  // 350 degrees one way is 10 the other
  EXPECT_NEAR(rotationAngleDegrees(identity, glm::dquat(glm::angleAxis(glm::radians(350.0), glm::dvec3(0, 0, 1)))),
              10.0, 1e-9);
}

// Guards eq. (4) and the child directions on a plain chain.
TEST(JpcError, ChainGeometry) {
  const std::vector<JointGeometry> geometry = jointGeometry(test::makeChain(3, 10.0f));
  ASSERT_EQ(geometry.size(), 3u);
  EXPECT_DOUBLE_EQ(geometry[0].radius, 20.0); // both descendants, not its own offset
  EXPECT_DOUBLE_EQ(geometry[1].radius, 10.0);
  EXPECT_DOUBLE_EQ(geometry[2].radius, 0.0);
  ASSERT_EQ(geometry[0].directions.size(), 1u);
  EXPECT_EQ(geometry[0].directions[0], glm::dvec3(0, 1, 0));
  ASSERT_EQ(geometry[1].directions.size(), 1u);
  EXPECT_TRUE(geometry[2].directions.empty()); // a leaf: E_pos = 0
}

// Guards the zero-length rule: a child at the joint's own position (CMU hips -> LHipJoint)
// is followed down every branch, composing the REST transforms in between.
TEST(JpcError, ZeroLengthChildrenAreFollowedDownEveryBranch) {
  Skeleton skeleton;
  const auto add = [&](const char* name, int parent, glm::vec3 offset, glm::quat rotation = glm::quat(1, 0, 0, 0)) {
    Joint joint;
    joint.name = name;
    joint.parent = parent;
    joint.rest.translation = offset;
    joint.rest.rotation = rotation;
    skeleton.joints.push_back(joint);
  };
  add("root", -1, {0, 0, 0});
  add("hip", 0, {0, 0, 0}, axisAngle(90.0f, {0, 0, 1})); // zero-length, turned 90 degrees about z
  add("left", 1, {-10, 0, 0});                           // seen from root: rotated to (0, -10, 0)
  add("pelvis", 1, {0, 0, 0});                           // zero-length again
  add("right", 3, {0, 0, 4});                            // seen from root: (0, 0, 4)
  add("spine", 0, {0, 5, 0});
  ASSERT_FALSE(skeleton.validate());
  const std::vector<JointGeometry> geometry = jointGeometry(skeleton);
  const std::vector<glm::dvec3>& d = geometry[0].directions;
  ASSERT_EQ(d.size(), 3u);
  EXPECT_NEAR(glm::length(d[0] - glm::dvec3(0, -1, 0)), 0.0, 1e-7);
  EXPECT_NEAR(glm::length(d[1] - glm::dvec3(0, 0, 1)), 0.0, 1e-7);
  EXPECT_NEAR(glm::length(d[2] - glm::dvec3(0, 1, 0)), 0.0, 1e-7);
  EXPECT_NEAR(geometry[0].radius, 10.0 + 4.0 + 5.0, 1e-6);
  EXPECT_EQ(geometry[1].directions.size(), 2u); // the hip itself sees left and right
  EXPECT_NEAR(geometry[1].radius, 14.0, 1e-6);
}

// Guards eqs. (1), (2), (5), (6) on hand-computed values: a swing of d degrees of j1
// gives E = r d + alpha d; a pure twist gives only alpha d.
TEST(JpcError, ChainSwingAndTwistValues) {
  const Skeleton chain = test::makeChain(3, 10.0f);
  const Clip clip = test::chainClip(chain, 4, [](int t) {
    switch (t) {
    case 0:
      return glm::quat(1, 0, 0, 0);
    case 1:
      return axisAngle(30.0f, {0, 0, 1}); // swing
    case 2:
      return axisAngle(40.0f, {0, 1, 0}); // twist about the child direction
    default:
      return axisAngle(90.0f, {1, 0, 0});
    }
  });
  const JointTrack withAlpha = test::chainTrack(clip, 5.0);
  EXPECT_NEAR(withAlpha.error(1, 0), 10.0 * 30.0 + 5.0 * 30.0, 1e-3);
  EXPECT_NEAR(withAlpha.error(2, 0), 5.0 * 40.0, 1e-3);
  EXPECT_NEAR(withAlpha.error(3, 0), 10.0 * 90.0 + 5.0 * 90.0, 1e-3);
  const JointTrack noAlpha = test::chainTrack(clip, 0.0);
  EXPECT_NEAR(noAlpha.error(1, 0), 300.0, 1e-3);
  EXPECT_EQ(noAlpha.error(2, 0), 0.0); // alpha = 0 ignores a pure twist, exactly
  EXPECT_NEAR(withAlpha.maxError(), (10.0 + 5.0) * 180.0, 1e-6);
}

// Guards eq. (5)'s "largest over the directions" for a joint with two children.
TEST(JpcError, SeveralDirectionsTakeTheLargest) {
  JointGeometry geometry;
  geometry.directions = {{1, 0, 0}, {0, 1, 0}};
  geometry.radius = 2.0;
  const std::vector<glm::quat> rotations = {glm::quat(1, 0, 0, 0), axisAngle(90.0f, {1, 0, 0})};
  const JointTrack track(geometry, 0.0, rotations);
  EXPECT_NEAR(track.error(1, 0), 2.0 * 90.0, 1e-3); // +x stays, +y turns 90 degrees
}

// Guards exact zero and exact symmetry on real data, every joint of the CMU clip.
TEST(JpcError, RealDataIsExactlyZeroAndSymmetric) {
  const Asset& asset = test::realAsset("BVH/01_01.bvh");
  const Clip& clip = asset.clips.front();
  const std::vector<JointGeometry> geometry = jointGeometry(asset.skeleton, 1e-6 * asset.unitScale);
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> frame(0, clip.frameCount - 1);
  for (int j = 0; j < clip.jointCount; ++j) {
    if (!clip.hasRotation[static_cast<std::size_t>(j)])
      continue;
    const JointTrack track(geometry[static_cast<std::size_t>(j)], 5.0, test::rotationsOf(clip, j));
    for (int i = 0; i < 2000; ++i) {
      const int t = frame(rng), u = frame(rng);
      ASSERT_EQ(track.error(t, t), 0.0);
      ASSERT_EQ(track.error(t, u), track.error(u, t));
      ASSERT_LE(track.error(t, u), track.maxError());
    }
  }
}

// Guards the CMU hips: three directions (LHipJoint and RHipJoint have zero-length offsets
// and are followed to the legs) and r = the whole body, about 446 cm at 5.6444 cm/unit.
TEST(JpcError, CmuHips) {
  const Asset& asset = test::realAsset("BVH/01_01.bvh");
  const std::vector<JointGeometry> geometry = jointGeometry(asset.skeleton, 1e-6 * asset.unitScale);
  EXPECT_EQ(geometry[0].directions.size(), 3u);
  EXPECT_NEAR(geometry[0].radius, 446.0, 1.0);
}

// Guards the float SIMD kernel against the scalar one: within its stated bound with 4x
// to spare, and within 1e-4 relative past one degree of motion (issue 3). The clustering
// relies on the bound to keep exact results.
void checkApproximation(const JointTrack& track, const std::vector<int>& refs, const std::string& what) {
  std::vector<float> approximate(static_cast<std::size_t>(track.frameCount()));
  for (int ref : refs) {
    track.approximateErrors(ref, 0, track.frameCount(), approximate.data());
    for (int t = 0; t < track.frameCount(); ++t) {
      const double exact = track.error(t, ref);
      const double difference = std::abs(approximate[static_cast<std::size_t>(t)] - exact);
      ASSERT_LE(difference, 0.25 * track.approximationBound()) << what << " t " << t << " ref " << ref;
      if (exact > track.radius() + track.alpha()) { // past one degree of motion; float resolves less near 0
        ASSERT_LE(difference, 1e-4 * exact) << what << " t " << t << " ref " << ref;
      }
    }
  }
  // a part of a row gives the same values as the whole row
  std::vector<float> part(5);
  track.approximateErrors(refs.front(), 1, 5, part.data());
  track.approximateErrors(refs.front(), 0, track.frameCount(), approximate.data());
  for (int i = 0; i < 5; ++i)
    EXPECT_EQ(part[static_cast<std::size_t>(i)], approximate[static_cast<std::size_t>(i) + 1]);
}

TEST(JpcError, ApproximateKernelOnRealData) {
  for (const char* file : {"BVH/01_01.bvh", "X/BCN_Epileptic.X"}) {
    const Asset& asset = test::realAsset(file);
    const Clip& clip = asset.clips.front();
    const std::vector<JointGeometry> geometry = jointGeometry(asset.skeleton, 1e-6 * asset.unitScale);
    for (double alpha : {0.0, 5.0, 100.0}) {
      for (int j = 0; j < clip.jointCount; ++j) {
        if (!clip.hasRotation[static_cast<std::size_t>(j)])
          continue;
        const JointTrack track(geometry[static_cast<std::size_t>(j)], alpha, test::rotationsOf(clip, j));
        std::vector<int> refs;
        for (int ref = 0; ref < clip.frameCount; ref += std::max(1, clip.frameCount / 13))
          refs.push_back(ref);
        checkApproximation(track, refs,
                           std::string(file) + " " + asset.skeleton.joints[static_cast<std::size_t>(j)].name);
        if (HasFatalFailure())
          return;
      }
    }
  }
}

// The hard cases for float: postures a hair apart, and nearly opposite (180 degrees).
TEST(JpcError, ApproximateKernelNearZeroAndNearOpposite) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::uniform_real_distribution<float> exponent(-7.0f, 0.0f);
  JointGeometry geometry;
  geometry.directions = {glm::normalize(glm::dvec3(0.3, 1.0, -0.2)), {1, 0, 0}};
  geometry.radius = 446.0;
  std::vector<glm::quat> rotations;
  for (int i = 0; i < 4000; ++i) {
    const glm::quat base = glm::normalize(glm::quat(unit(rng), unit(rng), unit(rng), unit(rng)));
    const float small = std::pow(10.0f, exponent(rng)); // degrees
    const glm::vec3 axis(unit(rng), unit(rng), unit(rng));
    rotations.push_back(base);
    rotations.push_back(glm::normalize(base * axisAngle(small, axis)));          // a hair apart
    rotations.push_back(glm::normalize(base * axisAngle(180.0f - small, axis))); // nearly opposite
  }
  for (double alpha : {0.0, 5.0}) {
    const JointTrack track(geometry, alpha, rotations);
    std::vector<float> approximate(2);
    for (int i = 0; i + 2 < track.frameCount(); i += 3) {
      track.approximateErrors(i, i + 1, 2, approximate.data());
      for (int k = 0; k < 2; ++k)
        ASSERT_LE(std::abs(approximate[static_cast<std::size_t>(k)] - track.error(i + 1 + k, i)),
                  0.25 * track.approximationBound())
            << i << " " << k;
    }
  }
}

} // namespace
} // namespace mlod
