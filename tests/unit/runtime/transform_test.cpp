#include "runtime/transform.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace mlod {
namespace {

void expectNear(const glm::mat4& a, const glm::mat4& b, float tolerance) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      EXPECT_NEAR(a[c][r], b[c][r], tolerance) << "column " << c << " row " << r;
}

// Guards the T * R * S order: a point is scaled, then rotated, then moved.
TEST(Transform, MatrixAppliesScaleThenRotationThenTranslation) {
  Transform t;
  t.translation = {10.0f, 0.0f, 0.0f};
  t.rotation = glm::angleAxis(glm::radians(90.0f), glm::vec3(0, 0, 1));
  t.scale = glm::vec3(2.0f);
  const glm::vec4 p = toMatrix(t) * glm::vec4(1, 0, 0, 1);
  EXPECT_NEAR(p.x, 10.0f, 1e-5f);
  EXPECT_NEAR(p.y, 2.0f, 1e-5f);
  EXPECT_NEAR(p.z, 0.0f, 1e-5f);
}

// Guards decompose() as the inverse of toMatrix(), including a non-uniform scale.
TEST(Transform, DecomposeInvertsToMatrix) {
  Transform t;
  t.translation = {1.5f, -2.0f, 30.0f};
  t.rotation = glm::normalize(glm::quat(0.3f, 0.5f, -0.2f, 0.7f));
  t.scale = {1.0f, 2.0f, 0.5f};
  const Transform back = decompose(toMatrix(t));
  expectNear(toMatrix(back), toMatrix(t), 1e-5f);
  EXPECT_NEAR(back.scale.y, 2.0f, 1e-5f);
}

// Guards mirrored matrices: the mirror goes into the x scale, the rotation stays proper.
TEST(Transform, DecomposeKeepsMirrorInScale) {
  const glm::mat4 mirror = glm::scale(glm::mat4(1.0f), glm::vec3(-1.0f, 1.0f, 1.0f));
  const Transform back = decompose(mirror);
  EXPECT_LT(back.scale.x, 0.0f);
  EXPECT_NEAR(std::abs(back.rotation.w), 1.0f, 1e-6f);
  expectNear(toMatrix(back), mirror, 1e-6f);
}

// Guards isValid(): every non-finite component and a non-unit rotation fail it.
TEST(Transform, ValidityRules) {
  EXPECT_TRUE(Transform{}.isValid());
  const float nan = std::numeric_limits<float>::quiet_NaN();
  Transform bad;
  bad.translation.y = nan;
  EXPECT_FALSE(bad.isValid());
  bad = {};
  bad.scale.z = std::numeric_limits<float>::infinity();
  EXPECT_FALSE(bad.isValid());
  bad = {};
  bad.rotation = glm::quat(2.0f, 0.0f, 0.0f, 0.0f);
  EXPECT_FALSE(bad.isValid());
  bad.rotation = glm::quat(nan, 0.0f, 0.0f, 0.0f);
  EXPECT_FALSE(bad.isValid());
}

} // namespace
} // namespace mlod
