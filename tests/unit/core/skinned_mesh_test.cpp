#include "core/skinned_mesh.h"

#include <gtest/gtest.h>

#include <limits>
#include <random>

namespace mlod {
namespace {

float floatSum(const glm::vec4& w) { return ((w.x + w.y) + w.z) + w.w; }

SkinnedMesh triangle() {
  SkinnedMesh mesh;
  mesh.name = "tri";
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.indices = {0, 1, 2};
  mesh.joints = std::vector<glm::u16vec4>(3, glm::u16vec4(0));
  mesh.weights = std::vector<glm::vec4>(3, glm::vec4(1, 0, 0, 0));
  return mesh;
}

// Guards the exact normalisation the Khronos validator needs (TOOLCHAIN.md): on random
// influence sets, with many exact thirds, the float sum is exactly 1 and slots are sorted.
TEST(NormalizeInfluences, SumIsExactlyOneAndSorted) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  int checked = 0;
  for (int trial = 0; trial < 200000; ++trial) {
    const int count = 1 + static_cast<int>(rng() % 6);
    int joints[6];
    float weights[6];
    for (int i = 0; i < count; ++i) {
      joints[i] = i + 10;
      weights[i] = rng() % 3 == 0 ? 1.0f / 3.0f : uniform(rng);
    }
    glm::u16vec4 outJoints;
    glm::vec4 outWeights;
    if (!normalizeInfluences(joints, weights, count, outJoints, outWeights))
      continue;
    ++checked;
    ASSERT_EQ(floatSum(outWeights), 1.0f) << "trial " << trial;
    ASSERT_GE(outWeights.x, outWeights.y) << "trial " << trial;
    ASSERT_GE(outWeights.y, outWeights.z) << "trial " << trial;
    ASSERT_GE(outWeights.z, outWeights.w) << "trial " << trial;
  }
  EXPECT_GT(checked, 190000);
}

// Guards the three-way tie of BCN_Epileptic.X's vertex 468 (found on real data).
TEST(NormalizeInfluences, ThreeEqualWeights) {
  const int joints[3] = {4, 5, 6};
  const float weights[3] = {1.0f / 3, 1.0f / 3, 1.0f / 3};
  glm::u16vec4 j;
  glm::vec4 w;
  ASSERT_TRUE(normalizeInfluences(joints, weights, 3, j, w));
  EXPECT_EQ(floatSum(w), 1.0f);
  EXPECT_GE(w.x, w.y);
  EXPECT_GE(w.y, w.z);
  EXPECT_EQ(w.w, 0.0f);
}

// Guards the 4-influence limit: the largest four are kept, the rest dropped and renormalised.
TEST(NormalizeInfluences, KeepsTheLargestFour) {
  const int joints[6] = {1, 2, 3, 4, 5, 6};
  const float weights[6] = {0.05f, 0.3f, 0.1f, 0.25f, 0.2f, 0.1f};
  glm::u16vec4 j;
  glm::vec4 w;
  ASSERT_TRUE(normalizeInfluences(joints, weights, 6, j, w));
  EXPECT_EQ(j, glm::u16vec4(2, 4, 5, 3)); // 0.3, 0.25, 0.2, then the first 0.1 (stable)
  EXPECT_NEAR(w.x, 0.3f / 0.85f, 1e-6f);
  EXPECT_EQ(floatSum(w), 1.0f);
}

// Guards vertices with no usable weight: reported, so the importer can bind them rigidly.
TEST(NormalizeInfluences, NoPositiveWeight) {
  const int joints[2] = {1, 2};
  const float weights[2] = {0.0f, -1.0f};
  glm::u16vec4 j;
  glm::vec4 w;
  EXPECT_FALSE(normalizeInfluences(joints, weights, 2, j, w));
  EXPECT_FALSE(normalizeInfluences(joints, weights, 0, j, w));
}

// Guards validate(): each broken rule in turn.
TEST(SkinnedMesh, ValidateRejectsEachRule) {
  const auto expectError = [](const SkinnedMesh& mesh, int jointCount, const std::string& fragment) {
    const Error error = mesh.validate(jointCount);
    ASSERT_TRUE(error) << "expected an error containing '" << fragment << "'";
    EXPECT_NE(error.message().find(fragment), std::string::npos) << error.message();
  };
  EXPECT_FALSE(triangle().validate(1));
  SkinnedMesh m = triangle();
  m.indices.clear();
  expectError(m, 1, "no vertices or no triangles");
  m = triangle();
  m.indices.push_back(0);
  expectError(m, 1, "multiple of 3");
  m = triangle();
  m.indices[1] = 3;
  expectError(m, 1, "out of range");
  m = triangle();
  m.normals = {{0, 0, 1}};
  expectError(m, 1, "normals or uvs");
  m = triangle();
  m.positions[2].x = std::numeric_limits<float>::quiet_NaN();
  expectError(m, 1, "non-finite vertex position");
  m = triangle();
  m.weights.pop_back();
  expectError(m, 1, "skin influences");
  m = triangle();
  expectError(m, 0, "does not exist");
  m = triangle();
  m.weights[1] = glm::vec4(0.5f, 0.6f, 0.0f, 0.0f);
  expectError(m, 1, "not sorted");
  m = triangle();
  m.weights[1] = glm::vec4(0.5f, 0.25f, 0.0f, 0.0f);
  expectError(m, 1, "do not sum to 1");
  m = triangle();
  m.weights[0].y = -0.0001f;
  expectError(m, 1, "invalid skin weight");
  m = triangle();
  m.parts.push_back({"p", 3, 3});
  expectError(m, 1, "outside its index range");
}

// Guards a mesh without a skeleton: a static mesh is valid with zero joints.
TEST(SkinnedMesh, StaticMeshNeedsNoSkeleton) {
  SkinnedMesh m = triangle();
  m.joints.clear();
  m.weights.clear();
  EXPECT_FALSE(m.skinned());
  EXPECT_FALSE(m.validate(0));
  EXPECT_EQ(m.boneCount(), 0);
}

} // namespace
} // namespace mlod
