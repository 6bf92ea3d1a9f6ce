// SkinningJob and SkinningMesh on the real character of assimp-testmodels (BCN_Epileptic.X:
// 54 bones, 3,014 vertices), posed by the evaluator from its own clip: equal to a
// straightforward reference loop; and validate() rejecting each invalid input in turn.

#include "runtime/pose_evaluator.h"
#include "runtime/skinning_job.h"
#include "unit/runtime/runtime_fixtures.h"

#include <gtest/gtest.h>

#include <vector>

namespace mlod {
namespace {

using test::runtimeAsset;

constexpr const char* kCharacter = "X/BCN_Epileptic.X";

const SkinnedMesh& characterMesh() {
  const Asset& asset = runtimeAsset(kCharacter);
  for (const SkinnedMesh& mesh : asset.meshes)
    if (mesh.skinned())
      return mesh;
  throw std::runtime_error("BCN_Epileptic.X has no skinned mesh");
}

// The palettes of the character's clip at a few times.
std::vector<std::vector<glm::mat4>> palettes() {
  const Asset& asset = runtimeAsset(kCharacter);
  const std::vector<std::int16_t> parents = asset.skeleton.parentIndices();
  const std::vector<glm::mat4> inverseBinds = paletteInverseBinds(asset.skeleton);
  Result<LodClip> clip = buildLodClip(asset.clips.front());
  if (!clip)
    throw std::runtime_error(clip.message());
  std::vector<std::vector<glm::mat4>> out;
  PoseEvaluatorContext context(1, asset.skeleton.jointCount());
  for (double ratio : {0.0, 0.37, 0.5, 1.0}) {
    const double time = ratio * clip->duration();
    const LodClip* clips[1] = {&*clip};
    std::vector<glm::mat4> palette(parents.size());
    PoseEvaluatorJob job;
    job.parents = parents;
    job.inverseBinds = inverseBinds;
    job.clips = clips;
    job.times = std::span<const double>(&time, 1);
    job.context = &context;
    job.out_palette = palette;
    if (!job.run())
      throw std::runtime_error("the pose job did not validate");
    out.push_back(std::move(palette));
  }
  return out;
}

// The reference: every vertex, its four (joint, weight) pairs as the mesh holds them.
void referenceSkin(const SkinnedMesh& mesh, const std::vector<glm::mat4>& palette, std::vector<glm::vec3>& positions,
                   std::vector<glm::vec3>& normals) {
  positions.resize(mesh.vertexCount());
  normals.resize(mesh.normals.size());
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    glm::mat4 blended(0.0f);
    for (int i = 0; i < 4; ++i)
      blended += palette[mesh.joints[v][i]] * mesh.weights[v][i];
    positions[v] = glm::vec3(blended * glm::vec4(mesh.positions[v], 1.0f));
    if (!mesh.normals.empty())
      normals[v] = glm::vec3(blended * glm::vec4(mesh.normals[v], 0.0f));
  }
}

bool near(const glm::vec3& a, const glm::vec3& b) {
  for (int i = 0; i < 3; ++i)
    if (!(std::abs(a[i] - b[i]) <= 1e-5f * std::max(1.0f, std::abs(b[i]))))
      return false;
  return true;
}

// Guards the split by influence count: every vertex lands in the group of its number of
// positive weights, once, and the groups cover the mesh.
TEST(SkinningMesh, GroupsVerticesByInfluenceCount) {
  const SkinnedMesh& mesh = characterMesh();
  Result<SkinningMesh> built = buildSkinningMesh(mesh, runtimeAsset(kCharacter).skeleton.jointCount());
  ASSERT_TRUE(built) << built.message();
  ASSERT_EQ(built->vertexCount(), static_cast<int>(mesh.vertexCount()));
  std::vector<int> seen(mesh.vertexCount(), 0);
  for (int k = 1; k <= 4; ++k)
    for (int i = built->groupBegin(k); i < built->groupBegin(k + 1); ++i) {
      const std::uint32_t v = built->order()[static_cast<std::size_t>(i)];
      ++seen[v];
      int positive = 0;
      for (int w = 0; w < 4; ++w)
        positive += mesh.weights[v][w] > 0.0f ? 1 : 0;
      EXPECT_EQ(positive, k) << "vertex " << v;
    }
  for (int count : seen)
    EXPECT_EQ(count, 1);
  for (int k = 1; k <= 4; ++k)
    RecordProperty("vertices with " + std::to_string(k) + " influences",
                   built->groupBegin(k + 1) - built->groupBegin(k));
}

// Guards LBS itself: positions and normals equal the reference loop at several poses.
TEST(SkinningJob, EqualsReferenceLoopOnRealCharacter) {
  const SkinnedMesh& mesh = characterMesh();
  ASSERT_FALSE(mesh.normals.empty());
  Result<SkinningMesh> built = buildSkinningMesh(mesh, runtimeAsset(kCharacter).skeleton.jointCount());
  ASSERT_TRUE(built) << built.message();
  std::vector<glm::vec3> positions(mesh.vertexCount()), normals(mesh.vertexCount());
  std::vector<glm::vec3> expectedPositions, expectedNormals;
  for (const std::vector<glm::mat4>& palette : palettes()) {
    ASSERT_TRUE(built->skin(palette, positions, normals));
    referenceSkin(mesh, palette, expectedPositions, expectedNormals);
    for (int i = 0; i < built->vertexCount(); ++i) {
      const std::uint32_t v = built->order()[static_cast<std::size_t>(i)];
      ASSERT_TRUE(near(positions[static_cast<std::size_t>(i)], expectedPositions[v])) << "vertex " << v;
      ASSERT_TRUE(near(normals[static_cast<std::size_t>(i)], expectedNormals[v])) << "normal of vertex " << v;
    }
  }
}

// Guards a mesh without normals: positions only.
TEST(SkinningJob, SkinsPositionsWithoutNormals) {
  const SkinnedMesh& mesh = characterMesh();
  const int joints = runtimeAsset(kCharacter).skeleton.jointCount();
  std::optional<SkinningMesh> built = SkinningMesh::build(mesh.positions, {}, mesh.joints, mesh.weights, joints);
  ASSERT_TRUE(built);
  EXPECT_FALSE(built->hasNormals());
  const std::vector<glm::mat4> palette = palettes()[1];
  std::vector<glm::vec3> positions(mesh.vertexCount()), expectedPositions, expectedNormals;
  ASSERT_TRUE(built->skin(palette, positions, {}));
  referenceSkin(mesh, palette, expectedPositions, expectedNormals);
  for (int i = 0; i < built->vertexCount(); ++i)
    ASSERT_TRUE(near(positions[static_cast<std::size_t>(i)], expectedPositions[built->order()[static_cast<std::size_t>(i)]]));
}

// Guards SkinningMesh::build()'s checks: bad influences are errors with a message.
TEST(SkinningMesh, RejectsBadInfluences) {
  const std::vector<glm::vec3> positions{{0, 0, 0}, {1, 0, 0}};
  const std::vector<glm::u16vec4> joints{{0, 1, 0, 0}, {1, 0, 0, 0}};
  const std::vector<glm::vec4> weights{{0.5f, 0.5f, 0, 0}, {1, 0, 0, 0}};
  std::string error;
  EXPECT_TRUE(SkinningMesh::build(positions, {}, joints, weights, 2, &error)) << error;
  EXPECT_FALSE(SkinningMesh::build(positions, {}, joints, weights, 1, &error)) << "joint 1 of 1";
  EXPECT_NE(error.find("joint"), std::string::npos);
  const std::vector<glm::vec4> none{{0.5f, 0.5f, 0, 0}, {0, 0, 0, 0}};
  EXPECT_FALSE(SkinningMesh::build(positions, {}, joints, none, 2, &error)) << "a vertex without weight";
  const std::vector<glm::vec4> nan{{0.5f, std::nanf(""), 0, 0}, {1, 0, 0, 0}};
  EXPECT_FALSE(SkinningMesh::build(positions, {}, joints, nan, 2, &error));
  EXPECT_FALSE(SkinningMesh::build(positions, {}, std::span<const glm::u16vec4>(joints.data(), 1), weights, 2, &error));
  EXPECT_FALSE(SkinningMesh::build({}, {}, {}, {}, 2, &error)) << "no vertices";
}

// Guards validate(): each invalid input in turn fails, and run() then writes nothing.
TEST(SkinningJob, RejectsInvalidJobs) {
  const std::vector<glm::mat4> palette(2, glm::mat4(1.0f));
  const std::vector<glm::vec3> positions{{1, 2, 3}, {4, 5, 6}};
  const std::vector<glm::vec3> normals{{0, 0, 1}, {0, 1, 0}};
  const std::vector<std::uint16_t> joints{0, 1, 1, 0};
  const std::vector<float> weights{0.5f, 0.5f, 0.25f, 0.75f};
  std::vector<glm::vec3> outPositions(2, glm::vec3(9.0f)), outNormals(2, glm::vec3(9.0f));
  const auto valid = [&] {
    SkinningJob job;
    job.influences = 2;
    job.palette = palette;
    job.joints = joints;
    job.weights = weights;
    job.positions = positions;
    job.normals = normals;
    job.out_positions = outPositions;
    job.out_normals = outNormals;
    return job;
  };
  ASSERT_TRUE(valid().validate());
  std::vector<SkinningJob> invalid;
  for (int influences : {0, 5}) {
    SkinningJob job = valid();
    job.influences = influences;
    invalid.push_back(job);
  }
  {
    SkinningJob job = valid();
    job.palette = {}; // no palette
    invalid.push_back(job);
  }
  {
    SkinningJob job = valid();
    job.out_positions = {}; // no output
    invalid.push_back(job);
  }
  {
    SkinningJob job = valid();
    job.out_normals = {}; // normals in, none out
    invalid.push_back(job);
  }
  {
    SkinningJob job = valid();
    job.joints = std::span<const std::uint16_t>(joints.data(), 3); // a joint short
    invalid.push_back(job);
  }
  {
    SkinningJob job = valid();
    job.weights = {}; // two influences need weights
    invalid.push_back(job);
  }
  {
    SkinningJob job = valid();
    job.out_positions = std::span<glm::vec3>(outPositions.data(), 1); // output too small
    invalid.push_back(job);
  }
  for (std::size_t i = 0; i < invalid.size(); ++i) {
    EXPECT_FALSE(invalid[i].validate()) << "case " << i;
    EXPECT_FALSE(invalid[i].run()) << "case " << i;
  }
  EXPECT_EQ(outPositions[0], glm::vec3(9.0f)) << "a failed run writes nothing";
  ASSERT_TRUE(valid().run());
  EXPECT_EQ(outPositions[0], glm::vec3(1, 2, 3)); // identity palette
}

} // namespace
} // namespace mlod
