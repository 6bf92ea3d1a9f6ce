// Segmentation by joint (Ahn & Wohn, section 5): dominant joints, shared vertices (0 < w < 1)
// and the locks that keep seams closed.

#include "core/mesh/mesh_segments.h"
#include "unit/core/mesh_lod_fixtures.h"

#include <gtest/gtest.h>

#include <set>

namespace mlod {
namespace {

TEST(MeshSegments, TubeHasTwoSegmentsAndItsBlendRingsAreShared) {
  const test::Tube tube = test::makeTube();
  const MeshSegmentation segmentation = segmentMesh(tube.mesh);
  ASSERT_EQ(segmentation.segmentCount(), 2);
  EXPECT_EQ(segmentation.segments[0].joint, 0);
  EXPECT_EQ(segmentation.segments[1].joint, 1);
  const int perRing = tube.sides + 1;
  // rings at y = 17 .. 23 cm blend the two joints
  EXPECT_EQ(tube.sharedRings, 7);
  EXPECT_EQ(segmentation.sharedVertices, tube.sharedRings * perRing);
  // the seam's two vertices per ring weld into one
  EXPECT_EQ(segmentation.weldedVertices, tube.rings * tube.sides);
  for (int r = 0; r < tube.rings; ++r)
    EXPECT_EQ(segmentation.weld[std::size_t(r * perRing + tube.sides)], std::uint32_t(r * perRing)) << "ring " << r;
}

TEST(MeshSegments, TubeLocksSharedRingsAndBordersOnly) {
  // guards the lock rule: open ends and the blend zone stay, everything else may collapse
  const test::Tube tube = test::makeTube();
  const MeshSegmentation segmentation = segmentMesh(tube.mesh);
  const int perRing = tube.sides + 1;
  for (int r = 0; r < tube.rings; ++r) {
    const bool shared = r >= 17 && r <= 23;
    const bool border = r == 0 || r == tube.rings - 1;
    for (int s = 0; s < perRing; ++s) {
      const std::size_t v = std::size_t(r * perRing + s);
      EXPECT_EQ(segmentation.shared[v], shared ? 1 : 0) << "ring " << r;
      if (shared || border) {
        EXPECT_EQ(segmentation.locked[v], 1) << "ring " << r;
      } else if ((r >= 1 && r <= 15) || (r >= 25 && r <= tube.rings - 2)) {
        EXPECT_EQ(segmentation.locked[v], 0) << "ring " << r << " is inside its segment";
      }
    }
  }
}

TEST(MeshSegments, StaticMeshIsOneSegmentWithoutSharedVertices) {
  test::Tube tube = test::makeTube(5, 8);
  tube.mesh.joints.clear();
  tube.mesh.weights.clear();
  const MeshSegmentation segmentation = segmentMesh(tube.mesh);
  ASSERT_EQ(segmentation.segmentCount(), 1);
  EXPECT_EQ(segmentation.segments[0].joint, -1);
  EXPECT_EQ(segmentation.sharedVertices, 0);
  EXPECT_EQ(segmentation.segments[0].triangles.size(), tube.mesh.triangleCount());
}

TEST(MeshSegments, BcnEpilepticClassifiesEveryVertexAsThePaperDoes) {
  const SkinnedMesh& mesh = test::bcnEpileptic().meshes.at(0);
  const MeshSegmentation segmentation = segmentMesh(mesh);
  int shared = 0;
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    const bool expected = mesh.weights[v].x < 1.0f; // sorted largest first, summing to 1
    EXPECT_EQ(segmentation.shared[v], expected ? 1 : 0) << "vertex " << v;
    shared += expected;
    if (expected) {
      EXPECT_EQ(segmentation.locked[v], 1) << "a shared vertex must be locked";
    }
  }
  EXPECT_EQ(segmentation.sharedVertices, shared);
  EXPECT_GT(shared, 0);
  EXPECT_LT(shared, int(mesh.vertexCount()));
  // every triangle goes to the dominant joint of one of its vertices
  std::set<int> joints;
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const int joint = segmentation.segments[std::size_t(segmentation.triangleSegment[t])].joint;
    joints.insert(joint);
    bool found = false;
    for (int k = 0; k < 3; ++k)
      found |= mesh.joints[mesh.indices[t * 3 + std::size_t(k)]].x == joint;
    EXPECT_TRUE(found) << "triangle " << t;
  }
  EXPECT_EQ(joints.size(), segmentation.segments.size());
  // an unlocked vertex lies inside one segment
  std::vector<int> segmentOf(mesh.vertexCount(), -1);
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = segmentation.weld[mesh.indices[t * 3 + std::size_t(k)]];
      if (segmentation.locked[v])
        continue;
      if (segmentOf[v] < 0)
        segmentOf[v] = segmentation.triangleSegment[t];
      EXPECT_EQ(segmentOf[v], segmentation.triangleSegment[t]) << "unlocked vertex " << v << " spans two segments";
    }
}

} // namespace
} // namespace mlod
