// Mesh LOD per joint segment (Ahn & Wohn, section 5) on a synthetic two-segment tube and on
// BCN_Epileptic: triangle counts, locked vertices, valid triangles and attributes, errors.

#include "core/mesh/mesh_lod.h"
#include "core/mesh/skinning.h"
#include "core/mesh/surface_distance.h"
#include "unit/core/mesh_lod_fixtures.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

namespace mlod {
namespace {

double triangleArea(const SkinnedMesh& mesh, std::size_t t) {
  const glm::dvec3 a(mesh.positions[mesh.indices[t * 3]]), b(mesh.positions[mesh.indices[t * 3 + 1]]),
      c(mesh.positions[mesh.indices[t * 3 + 2]]);
  return 0.5 * glm::length(glm::cross(b - a, c - a));
}

// A triangle is flipped when its geometric normal points against its vertices' normals.
bool flipped(const SkinnedMesh& mesh, std::size_t t) {
  const glm::vec3 a = mesh.positions[mesh.indices[t * 3]], b = mesh.positions[mesh.indices[t * 3 + 1]],
                  c = mesh.positions[mesh.indices[t * 3 + 2]];
  const glm::vec3 n = glm::cross(b - a, c - a);
  const glm::vec3 shading =
      mesh.normals[mesh.indices[t * 3]] + mesh.normals[mesh.indices[t * 3 + 1]] + mesh.normals[mesh.indices[t * 3 + 2]];
  return glm::dot(n, shading) < 0.0f;
}

using TriangleKey = std::array<std::uint32_t, 3>;
TriangleKey key(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  if (a <= b && a <= c)
    return {a, b, c};
  if (b <= a && b <= c)
    return {b, c, a};
  return {c, a, b};
}

// The checks every level must pass, whatever its ratio.
void expectValidLevel(const MeshLod& lod, const MeshLodLevel& level, const std::string& what) {
  SCOPED_TRACE(what);
  const SkinnedMesh& original = lod.original();
  const SkinnedMesh& mesh = level.mesh;
  // weights (<= 4 influences, sorted, exact sums), normals, UVs, parts: the mesh validates
  ASSERT_FALSE(mesh.validate(65536)) << mesh.validate(65536).message();
  ASSERT_EQ(level.sourceVertices.size(), mesh.vertexCount());
  std::set<TriangleKey> originalTriangles;
  for (std::size_t t = 0; t < original.triangleCount(); ++t)
    originalTriangles.insert(key(original.indices[t * 3], original.indices[t * 3 + 1], original.indices[t * 3 + 2]));
  // every vertex is an original one, attributes and all
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    const std::uint32_t s = level.sourceVertices[v];
    ASSERT_LT(s, original.vertexCount());
    EXPECT_EQ(mesh.positions[v], original.positions[s]);
    EXPECT_EQ(mesh.normals[v], original.normals[s]);
    EXPECT_EQ(mesh.uvs[v], original.uvs[s]);
    EXPECT_EQ(mesh.joints[v], original.joints[s]);
    EXPECT_EQ(mesh.weights[v], original.weights[s]);
  }
  // shared and border vertices: still there, where they were
  std::set<std::uint32_t> kept(level.sourceVertices.begin(), level.sourceVertices.end());
  std::set<std::uint32_t> used(original.indices.begin(), original.indices.end());
  int missing = 0;
  for (std::uint32_t v : used)
    if (lod.progressive().locked()[v] && !kept.count(v))
      ++missing;
  EXPECT_EQ(missing, 0) << "locked vertices dropped";
  EXPECT_TRUE(level.sharedVerticesPreserved);
  // no degenerate or flipped triangle that the original did not have
  int degenerate = 0, flips = 0;
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const TriangleKey k = key(level.sourceVertices[mesh.indices[t * 3]], level.sourceVertices[mesh.indices[t * 3 + 1]],
                              level.sourceVertices[mesh.indices[t * 3 + 2]]);
    if (originalTriangles.count(k))
      continue; // an original triangle, unchanged
    degenerate += !(triangleArea(mesh, t) > 1e-9);
    flips += flipped(mesh, t);
  }
  EXPECT_EQ(degenerate, 0);
  EXPECT_EQ(flips, 0);
  // the error is a distance the level really has (bind pose)
  EXPECT_GE(level.maxErrorCm, level.bindErrorCm);
  EXPECT_GE(level.maxErrorCm, level.animatedErrorCm);
}

TEST(MeshLodTube, RatiosReachTheirTriangleCountsWithinTenPercent) {
  const test::Tube tube = test::makeTube();
  const Clip bend = test::tubeBendClip(tube.skeleton);
  Result<MeshLod> lod = MeshLod::build(tube.mesh, &tube.skeleton, std::span<const Clip>(&bend, 1));
  ASSERT_TRUE(lod) << lod.message();
  const std::size_t total = tube.mesh.triangleCount();
  ASSERT_EQ(total, 1280u);
  for (double ratio : {0.9, 0.75, 0.6, 0.5}) {
    const MeshLodLevel level = lod->levelForRatio(ratio);
    const double target = ratio * double(total);
    EXPECT_LE(std::abs(double(level.triangles()) - target), 0.1 * target) << "ratio " << ratio;
    EXPECT_TRUE(level.warning.empty()) << level.warning;
    expectValidLevel(*lod, level, "tube at ratio " + std::to_string(ratio));
  }
}

TEST(MeshLodTube, TheUvSeamNeverWrapsAcrossTheTexture) {
  // guards the wedge rules: a collapse along the seam keeps each side on its side, so no
  // triangle ends up with u from both ends of the texture (0 ... 1 wrapped)
  const test::Tube tube = test::makeTube();
  Result<MeshLod> lod = MeshLod::build(tube.mesh);
  ASSERT_TRUE(lod) << lod.message();
  const MeshLodLevel level = lod->levelAt(lod->progressive().collapseCount());
  int seamCollapses = 0;
  for (std::size_t t = 0; t < level.mesh.triangleCount(); ++t) {
    float lo = 1.0f, hi = 0.0f;
    for (int k = 0; k < 3; ++k) {
      const float u = level.mesh.uvs[level.mesh.indices[t * 3 + std::size_t(k)]].x;
      lo = std::min(lo, u);
      hi = std::max(hi, u);
    }
    EXPECT_LE(hi - lo, 0.5f) << "triangle " << t << " spans the texture";
  }
  // and the seam did simplify: fewer seam vertices remain than the tube had
  for (std::uint32_t s : level.sourceVertices)
    seamCollapses += (s % std::uint32_t(tube.sides + 1)) == std::uint32_t(tube.sides);
  EXPECT_LT(seamCollapses, tube.rings);
  expectValidLevel(*lod, level, "tube fully simplified");
}

TEST(MeshLodTube, ARatioBelowWhatLocksAllowWarnsWithTheCountReached) {
  const test::Tube tube = test::makeTube();
  Result<MeshLod> lod = MeshLod::build(tube.mesh);
  ASSERT_TRUE(lod) << lod.message();
  const MeshLodLevel level = lod->levelForRatio(0.05);
  EXPECT_FALSE(level.warning.empty());
  EXPECT_EQ(level.triangles(), lod->progressive().minTriangleCount());
  EXPECT_NE(level.warning.find(std::to_string(level.triangles())), std::string::npos) << level.warning;
  EXPECT_GT(level.triangles(), level.targetTriangles);
  expectValidLevel(*lod, level, "tube at 5%");
}

TEST(MeshLodTube, ErrorsGrowAsTheRatioFalls) {
  const test::Tube tube = test::makeTube();
  const Clip bend = test::tubeBendClip(tube.skeleton);
  Result<MeshLod> lod = MeshLod::build(tube.mesh, &tube.skeleton, std::span<const Clip>(&bend, 1));
  ASSERT_TRUE(lod) << lod.message();
  double previous = 0.0;
  for (double ratio : {1.0, 0.9, 0.8, 0.7, 0.6, 0.5, 0.4}) {
    const MeshLodLevel level = lod->levelForRatio(ratio);
    EXPECT_GE(level.maxErrorCm, previous) << "ratio " << ratio;
    previous = level.maxErrorCm;
  }
  EXPECT_GT(previous, 0.0);
}

TEST(MeshLodTube, ALevelByErrorStaysWithinIt) {
  const test::Tube tube = test::makeTube();
  const Clip bend = test::tubeBendClip(tube.skeleton);
  Result<MeshLod> lod = MeshLod::build(tube.mesh, &tube.skeleton, std::span<const Clip>(&bend, 1));
  ASSERT_TRUE(lod) << lod.message();
  for (double cm : {0.05, 0.2, 0.5}) {
    const MeshLodLevel level = lod->levelForError(cm);
    EXPECT_LE(level.maxErrorCm, cm);
    EXPECT_LT(level.triangles(), tube.mesh.triangleCount()) << cm << " cm allows some simplification";
    if (level.collapses < lod->progressive().collapseCount()) {
      EXPECT_GT(lod->errorsAt(level.collapses + 1).maxCm(), cm) << "one more collapse would exceed " << cm;
    }
  }
  // the straight tube's flat rings can go with no error at all in the bind pose
  EXPECT_EQ(lod->levelForError(0.0).maxErrorCm, 0.0);
}

TEST(MeshLodTube, ErrorIsMeasuredInAnimatedPosesToo) {
  // a collapse across the blend zone is flat at bind time and not once the tube bends
  const test::Tube tube = test::makeTube();
  const Clip bend = test::tubeBendClip(tube.skeleton);
  Result<MeshLod> lod = MeshLod::build(tube.mesh, &tube.skeleton, std::span<const Clip>(&bend, 1));
  ASSERT_TRUE(lod) << lod.message();
  EXPECT_EQ(lod->posePositions().size(), 1u + 8u); // bind + 8 frames of the clip
  const MeshLodLevel level = lod->levelForRatio(0.5);
  // recompute the animated error independently, pose by pose
  double worst = 0.0;
  const auto& frames = lod->poseFrames();
  std::vector<std::uint32_t> simplified;
  for (std::uint32_t i : level.mesh.indices)
    simplified.push_back(level.sourceVertices[i]);
  for (std::size_t p = 1; p < frames.size(); ++p) {
    const std::vector<glm::vec3> posed = posedPositions(tube.mesh, tube.skeleton, bend, frames[p].second);
    // whole-surface distance: a lower bound of the per-segment one the level reports
    worst = std::max(worst, symmetricMaxDistance(posed, tube.mesh.indices, simplified, lod->samplingSpacingCm()));
  }
  EXPECT_LE(worst, level.animatedErrorCm + 1e-6);
  EXPECT_GT(level.animatedErrorCm, 0.0);
}

TEST(MeshLodTube, BadSettingsAndInputAreErrors) {
  const test::Tube tube = test::makeTube(5, 8);
  MeshLodSettings settings;
  settings.decimation.maxNormalDeviationDegrees = 0.0;
  EXPECT_FALSE(MeshLod::build(tube.mesh, nullptr, {}, settings));
  settings = {};
  settings.samplingSpacingCm = -1.0;
  EXPECT_FALSE(MeshLod::build(tube.mesh, nullptr, {}, settings));
  SkinnedMesh broken = tube.mesh;
  broken.indices.push_back(9999);
  EXPECT_FALSE(MeshLod::build(broken));
  const Clip bend = test::tubeBendClip(tube.skeleton);
  EXPECT_FALSE(MeshLod::build(tube.mesh, nullptr, std::span<const Clip>(&bend, 1))) << "clips need a skeleton";
}

class MeshLodBcn : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    const Asset& asset = test::bcnEpileptic();
    Result<MeshLod> built = MeshLod::build(asset.meshes.at(0), &asset.skeleton, asset.clips);
    ASSERT_TRUE(built) << built.message();
    s_lod = new MeshLod(std::move(built).value());
  }
  static void TearDownTestSuite() {
    delete s_lod;
    s_lod = nullptr;
  }
  static MeshLod* s_lod;
};
MeshLod* MeshLodBcn::s_lod = nullptr;

TEST_F(MeshLodBcn, RatiosReachTheirTriangleCountsWithinTenPercent) {
  const std::size_t total = s_lod->original().triangleCount();
  ASSERT_EQ(total, 5126u);
  for (double ratio : {0.9, 0.75, 0.6, 0.5}) {
    const MeshLodLevel level = s_lod->levelForRatio(ratio);
    const double target = ratio * double(total);
    EXPECT_LE(std::abs(double(level.triangles()) - target), 0.1 * target) << "ratio " << ratio;
    // with 44% of the vertices shared between joints, 50% is just out of reach: it warns
    EXPECT_EQ(level.warning.empty(), level.triangles() <= level.targetTriangles) << level.warning;
    expectValidLevel(*s_lod, level, "BCN_Epileptic at ratio " + std::to_string(ratio));
  }
}

TEST_F(MeshLodBcn, ErrorsGrowAsTheRatioFalls) {
  double previousBind = 0.0, previousMax = 0.0;
  for (double ratio : {1.0, 0.95, 0.9, 0.8, 0.7, 0.6, 0.5}) {
    const MeshLodLevel level = s_lod->levelForRatio(ratio);
    EXPECT_GE(level.bindErrorCm, previousBind) << "ratio " << ratio;
    EXPECT_GE(level.maxErrorCm, previousMax) << "ratio " << ratio;
    previousBind = level.bindErrorCm;
    previousMax = level.maxErrorCm;
  }
}

TEST_F(MeshLodBcn, LevelsAreNestedAndCountsMatchTheProgressiveMesh) {
  const ProgressiveMesh& pm = s_lod->progressive();
  EXPECT_EQ(pm.trianglesAfter(0), 5126u);
  for (std::size_t k : {std::size_t(0), std::size_t(1), pm.collapseCount() / 3, pm.collapseCount()}) {
    const MeshLevelIndices level = pm.level(k);
    EXPECT_EQ(level.triangles.size(), pm.trianglesAfter(k)) << "k = " << k;
    EXPECT_EQ(level.indices.size(), level.triangles.size() * 3);
  }
  // the error estimate of the order grows with it
  for (std::size_t k = 1; k < pm.collapseCount(); ++k)
    ASSERT_LE(pm.costAt(k), pm.costAt(k + 1));
  // the per-segment view agrees with the global one
  const std::vector<std::size_t> perSegment = pm.segmentCollapses(pm.collapseCount() / 2);
  EXPECT_EQ(pm.levelPerSegment(perSegment).indices, pm.level(pm.collapseCount() / 2).indices);
}

} // namespace
} // namespace mlod
