#pragma once
// A skinned mesh split by joint segment, with the vertices that must never move
// (Ahn & Wohn, "Motion Level-of-Detail", section 5: "We divided the vertex list by each
// joint ... we divided the local vertex list into the shared vertex area and the
// non-shared vertex area. The weighting value of the shared vertex is (0 < w < 1), and of
// the non-shared vertex, (w = 1).").
//
// - A vertex belongs to the segment of its dominant joint (its largest weight; weights are
//   sorted largest first, so joints.x).
// - A vertex is *shared* when one of its weights lies strictly between 0 and 1.
// - A triangle belongs to the segment of its non-shared vertices (the lowest joint index
//   where they disagree), else to the joint most of its vertices are dominated by (ties:
//   the lowest index). So a non-shared vertex is inside its own segment whenever every
//   neighbour of it is shared or of its joint.
// - Topology is read on *welded* vertices: corners with the same position bits and the
//   same influences are one surface point, so attribute seams (UV or normal splits) are
//   not borders and can be simplified along (see progressive_mesh.h).
// - A welded vertex is *locked* when it is shared, lies on its segment's border (an edge
//   used once inside the segment, which covers mesh borders and segment seams), touches a
//   non-manifold edge (three or more triangles), or is used by two segments. Locked
//   vertices keep their position and their triangles fans stay closed, so no seam opens
//   between segments that deform differently.
//
// A mesh without skin weights is one segment (joint -1) with no shared vertex.

#include "core/skinned_mesh.h"

#include <cstdint>
#include <vector>

namespace mlod {

struct MeshSegment {
  int joint = -1;                       // the dominant joint; -1 for a static mesh
  std::vector<std::uint32_t> triangles; // triangle indices into the mesh (index / 3), ascending
};

struct MeshSegmentation {
  std::vector<MeshSegment> segments;      // ascending joint
  std::vector<int> triangleSegment;       // per triangle: index into segments
  std::vector<std::uint32_t> weld;        // per vertex: its welded vertex (the lowest vertex index of its group)
  std::vector<std::uint8_t> shared;       // per vertex: 1 where some weight is in (0, 1)
  std::vector<std::uint8_t> locked;       // per vertex: 1 where its welded vertex is locked (see above)
  int sharedVertices = 0;                 // count of vertices with shared = 1
  int lockedVertices = 0;                 // count of vertices with locked = 1 (referenced or not)
  int weldedVertices = 0;                 // distinct welded vertices

  int segmentCount() const { return static_cast<int>(segments.size()); }
};

// Splits `mesh` (which must validate) into segments and classifies its vertices.
// Deterministic; linear in the mesh size (plus a sort of its edges).
MeshSegmentation segmentMesh(const SkinnedMesh& mesh);

} // namespace mlod
