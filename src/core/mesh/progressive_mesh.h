#pragma once
// A progressive mesh of a skinned mesh, built per joint segment with OpenMesh's
// Decimater (Ahn & Wohn, section 5: "applied progressive mesh [Hoppe 1996] to each joint
// segment"; the collapse order is Garland & Heckbert's quadric error, "Surface
// Simplification Using Quadric Error Metrics", 1997, as OpenMesh's ModQuadric computes it).
//
// Each segment of segmentMesh() is decimated to the end by halfedge collapses (a vertex
// v0 merges into a neighbour v1 that keeps its position), guarded by ModNormalFlipping (no
// face normal turns by more than maxNormalDeviationDegrees in one collapse) and
// ModAspectRatio (no collapse makes a triangle thinner than maxAspectRatio where it was
// not already); ModProgMesh records the sequence. Locked vertices (mesh_segments.h) never
// collapse, so shared vertices and every border keep their place and no seam opens.
//
// Attributes stay valid by construction: a collapse only drops vertices, every remaining
// corner is an original vertex with its own normal, UV and skin weights. Corners are
// tracked per wedge (an original vertex index) on top of the welded topology: a vertex
// with one wedge may collapse into any neighbour whose two corners beside the edge agree;
// a vertex on an attribute seam (two wedges, two seam edges) only along its seam, each side
// onto the matching side; anything more complex never collapses.
//
// The segments' sequences merge into one global order by an error estimate in cm, both ways
// round: as OpenMesh's ModHausdorff does, every removed vertex stays attached to its nearest
// face, and a collapse costs the farthest of the re-attached vertices from the surface after
// it, or the farthest centroid or edge midpoint of the faces around v1 from the segment's
// original surface, whichever is larger; the running maximum of that within a segment keeps
// each segment's own order. Quadric errors
// are area-weighted sums (cm^4) that cannot be compared between segments; this estimate
// can, and it follows the measured maximum distance. The first k collapses of the global
// order give a mesh for any k, and so any triangle count between triangleCount() and
// minTriangleCount().

#include "core/mesh/mesh_segments.h"
#include "core/skinned_mesh.h"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace mlod {

struct ProgressiveMeshSettings {
  double maxNormalDeviationDegrees = 90.0; // per collapse, degrees in (0, 180]; OpenMesh's default
  // Longest edge over height a collapse may not exceed (where the triangle was not already
  // worse); 0 = no aspect-ratio guard. OpenMesh's default, 5, stops BCN_Epileptic at 57% of
  // its triangles where the locks allow 52%, and raises its error at equal triangle
  // counts; 20 still forbids slivers.
  double maxAspectRatio = 20.0;
};

// Triangles of one level, in the original triangle order.
struct MeshLevelIndices {
  std::vector<std::uint32_t> indices;   // into the original mesh's vertices
  std::vector<std::uint32_t> triangles; // per triangle: the original triangle it comes from
};

class ProgressiveMesh {
public:
  // Decimates every segment of `mesh` (which must validate; `segmentation` from
  // segmentMesh(mesh)) to the end: BCN_Epileptic (5,126 triangles, 54 segments, 1,230
  // collapses) in about 45 ms on one core.
  static ProgressiveMesh build(const SkinnedMesh& mesh, const MeshSegmentation& segmentation,
                               const ProgressiveMeshSettings& settings = {});

  std::size_t triangleCount() const { return m_triangleCount; } // before any collapse
  std::size_t collapseCount() const { return m_order.size(); }
  // Triangles after the first `collapses` collapses of the global order.
  std::size_t trianglesAfter(std::size_t collapses) const { return m_trianglesAfter[collapses]; }
  std::size_t minTriangleCount() const { return m_trianglesAfter.back(); }
  // The fewest collapses that leave at most `triangles` triangles; collapseCount() when
  // even all of them leave more.
  std::size_t collapsesFor(std::size_t triangles) const;
  // The error estimate (cm) of the global order at `collapses`: the largest distance of a
  // removed vertex from its segment's surface so far, over the segments collapsed; 0 for none.
  double costAt(std::size_t collapses) const;

  // Per vertex: 1 where it never collapses (the segmentation's locks, plus the vertices of
  // triangles OpenMesh could not hold, such as non-manifold fans).
  const std::vector<std::uint8_t>& locked() const { return m_locked; }
  int lockedCount() const { return m_lockedCount; }

  int segmentCount() const { return static_cast<int>(m_segments.size()); }
  std::size_t segmentCollapseCount(int segment) const;
  std::size_t segmentTriangleCount(int segment) const;
  std::size_t segmentTrianglesAfter(int segment, std::size_t collapses) const;
  // The error estimate (cm) of a segment after its first `collapses` collapses; 0 for none.
  double segmentCostAt(int segment, std::size_t collapses) const;
  // How many of each segment's collapses the first `collapses` of the global order take.
  std::vector<std::size_t> segmentCollapses(std::size_t collapses) const;

  // The mesh after the first `collapses` collapses of the global order (<= collapseCount()).
  MeshLevelIndices level(std::size_t collapses) const;
  // The mesh after the first perSegment[s] collapses of each segment s.
  MeshLevelIndices levelPerSegment(std::span<const std::size_t> perSegment) const;

private:
  struct Collapse {
    std::uint32_t from[2] = {0, 0}; // wedges (original vertices) that disappear
    std::uint32_t to[2] = {0, 0};   // the wedge each one becomes
    std::uint8_t wedges = 0;        // 1 or 2
    std::uint8_t removedTriangles = 0;
    double cost = 0.0; // cm: running maximum of the segment's error estimates
  };
  struct Segment {
    std::vector<Collapse> collapses;
    std::size_t triangles = 0;
  };
  struct OrderEntry {
    int segment = 0;
    std::uint32_t index = 0;
  };

  MeshLevelIndices extract(const std::vector<std::uint32_t>& target) const;

  std::vector<std::uint32_t> m_indices; // the original triangles
  std::vector<std::uint32_t> m_weld;    // per vertex
  std::vector<std::uint8_t> m_locked;
  int m_lockedCount = 0;
  std::size_t m_triangleCount = 0;
  std::vector<Segment> m_segments;
  std::vector<OrderEntry> m_order;           // global collapse order
  std::vector<std::size_t> m_trianglesAfter; // [k]: triangles after k collapses, k = 0 .. collapseCount()
};

} // namespace mlod
