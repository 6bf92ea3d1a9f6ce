#pragma once
// A progressive mesh of a whole skinned mesh, welded by position, simplified by halfedge collapses
// whose cost sees the motion (docs/architecture.md section 1, Geometric LOD).
//
// Garland & Heckbert, "Surface Simplification Using Quadric Error Metrics" (1997), with the
// quadrics accumulated over several poses of the skinned surface instead of one: each vertex keeps
// one quadric per pose (the bind pose and poses of the clips the character plays), and a
// collapse u -> v costs sum over poses p of Q_u^p(x_v^p) per unit of the weight u's quadrics gathered (a
// weighted mean squared distance, as meshoptimizer 0.18 ranks its collapses; triangles weigh the
// square root of their area, border and seam edges their length: the sum of area weights would rank
// a small part that moves far, an eye or a finger tip, below a large part that moves a little), so
// a collapse that looks harmless in the bind pose but folds an elbow or a knee when it bends costs
// what it costs there. Halfedge collapses keep the original vertices (v keeps its position, normal,
// UV and skin weights), so every level is drawn with the original vertex data and skins exactly
// like the original.
//
// Topology is read on welded vertices: corners with the same position bits and, on a skinned mesh,
// the same influences (corners at one place that different weights move apart are two surface
// points: welding them would tear the skin in motion). The welded mesh is an OpenMesh halfedge mesh
// (TriMesh_ArrayKernelT): OpenMesh keeps the connectivity, answers boundary and manifold queries,
// tests each collapse's link condition (is_collapse_ok) and performs it (collapse); the costs, the
// rules below, the queue and the pruning are ours. The corners of one welded vertex are its
// *wedges* (attribute seams: UV or normal splits); each halfedge carries the wedge it starts from
// in its triangle. What may collapse, after meshoptimizer's simplifier (Kapoulkine,
// src/simplifier.cpp):
//  - a vertex collapses along an edge whose triangles map each of its wedges to exactly one wedge
//    of the target: an interior vertex without a seam onto any neighbour; a seam vertex (two
//    wedges) only along its seam, both sides at once, each onto its own side, so no crack and no
//    T-junction opens along a seam;
//  - seams are a cost, not a wall: a collapse may also move a wedge that the edge's triangles do
//    not map (corners of three or more wedges, a seam left across, a flat-shaded mesh) onto the
//    target's wedge with the nearest attributes (normal, then UV). Such *attribute collapses* rank
//    with the clean ones by their cost, which the seam's edge quadrics raise; positions stay
//    welded, so they open no crack either, only an attribute discontinuity;
//  - a vertex on an open border only along the border, onto a border vertex, so no interior edge
//    becomes a border; the border is kept by edge quadrics of `borderWeight` (planes through each
//    border edge, perpendicular to its triangle), a cost rather than a wall, and so is a fold (two
//    triangles back to back, the end of a thin sheet); seam edges get the same with `seamWeight`;
//  - hard locks are non-manifold guards only: a welded vertex of several fans (triangles around it
//    joined through edges that two triangles share in opposite directions, and no other: a bowtie,
//    an edge of three triangles, or of two in one direction) is one OpenMesh vertex per fan, and
//    every copy is locked, as are the vertices of a degenerate input triangle (kept as it is);
//  - a collapse must keep the mesh manifold (OpenMesh's is_collapse_ok: the link condition; a
//    triangle standing alone, which OpenMesh will not collapse, is removed by ours) and flip no
//    triangle's normal in any pose.
// Beyond geometry, a collapse between vertices with different skin influences costs more:
// skinWeight x (1 - sum_j min(w_u[j], w_v[j])) x |u - v|^2 x importance (the skin weight mass that
// changes bone), so bones keep their own vertices. Per-vertex importance (the joints' mesh
// importance, weighted by the skin) scales the vertex's quadrics (not the area they are divided
// by), and so the cost of removing it and of everything later merged into it. A small move term,
// moveWeight x |u - v|^2 x importance, ranks collapses the quadrics see as free.
//
// A closed component cannot collapse below a tetrahedron, so a mesh of many small closed parts (64
// cubes) stops far above 10% by collapses alone. A step may also *prune* a whole connected
// component (after meshoptimizer's prune option), costed in the same metric: sum over poses of its
// quadrics' weight times its radius squared in that pose, per unit of its weight (what moving all
// its vertices that far costs). Prunings rank with the collapses; a component with a locked vertex
// or a degenerate triangle is never pruned, nor the last one with triangles.
//
// The steps run greedily by cost (a priority queue, re-ranked around each collapse) until none is
// allowed; the first k give a mesh for any k, so one build serves every triangle count down to
// minTriangleCount().

#include "core/skinned_mesh.h"

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

namespace mlod {

struct ProgressiveMeshSettings {
  // Edge quadric weight of open borders and folds, relative to the triangles' plane quadrics
  // (>= 0; 0 lets a border shrink freely).
  // note: triangles weigh sqrt(area) and edges their length, as in meshoptimizer, whose 10 and
  // 1 assume that its error divides by the edges' weight too; ours divides by the triangles'
  // alone, and 1 and 0.1 measure best on every character of bench_meshlod (its notes)
  double borderWeight = 1.0;
  // Edge quadric weight of attribute seams (>= 0).
  double seamWeight = 0.1;
  // Weight of the skin term (>= 0; 0 = geometry alone).
  double skinWeight = 1.0;
  // Weight of the move term (>= 0): moveWeight x area(u) x |u - v|^2, the distance a
  // collapse moves u in the bind pose, so that collapses the quadrics see as free (along a
  // ridge) still rank by how far they move the surface.
  double moveWeight = 0.01;
};

// Triangles of one level, in the original triangle order.
struct MeshLevelIndices {
  std::vector<std::uint32_t> indices;   // into the original mesh's vertices
  std::vector<std::uint32_t> triangles; // per triangle: the original triangle it comes from, ascending
};

class ProgressiveMesh {
public:
  // Simplifies `mesh` (which must validate) to the end. `poses`: skinned positions of every
  // vertex of `mesh` per pose (cm; at least one, [0] the bind pose, each of mesh.vertexCount()
  // entries). `vertexImportance`: per vertex, > 0, or empty for 1 everywhere. `cancel`
  // (core/cancel.h, may be null) is looked at every few hundred collapses: once it is set the
  // order stops where it is, so a cancelled build is incomplete and the caller drops it.
  static ProgressiveMesh build(const SkinnedMesh& mesh, std::span<const std::vector<glm::vec3>> poses,
                               std::span<const float> vertexImportance = {},
                               const ProgressiveMeshSettings& settings = {}, const std::atomic<bool>* cancel = nullptr);

  std::size_t triangleCount() const { return m_triangleCount; } // before any collapse
  std::size_t collapseCount() const { return m_collapses.size(); }
  // Triangles after the first `collapses` collapses.
  std::size_t trianglesAfter(std::size_t collapses) const { return m_trianglesAfter[collapses]; }
  std::size_t minTriangleCount() const { return m_trianglesAfter.back(); }
  // The fewest collapses that leave at most `triangles` triangles; collapseCount() when
  // even all of them leave more.
  std::size_t collapsesFor(std::size_t triangles) const;
  // The quadric cost of collapse k (0-based), in cm^2 (the sum over poses of weighted squared
  // distances, per unit of weight): for ordering, not a distance.
  double costOf(std::size_t collapse) const { return m_collapses[collapse].cost; }
  // Collapses before the first attribute collapse or pruning (collapseCount() when there is none).
  std::size_t cleanCollapseCount() const { return m_cleanCollapses; }

  // Per vertex: its welded vertex (the lowest vertex index at the same position with the same
  // influences).
  const std::vector<std::uint32_t>& weld() const { return m_weld; }
  // Per vertex: 1 where it never collapses (the non-manifold guards above).
  const std::vector<std::uint8_t>& locked() const { return m_locked; }
  int lockedCount() const { return m_lockedCount; } // welded vertices locked
  int weldedVertexCount() const { return m_weldedCount; }

  // The mesh after the first `collapses` collapses (<= collapseCount()).
  MeshLevelIndices level(std::size_t collapses) const;

private:
  // One step: a collapse (wedges moved), or a component's pruning (triangles removed).
  struct Collapse {
    std::uint32_t firstWedge = 0; // into m_from / m_to: the wedges that disappear, and what each becomes
    std::uint32_t wedgeCount = 0;
    std::uint32_t firstPruned = 0; // into m_pruned: the triangles a pruning removes
    std::uint32_t prunedCount = 0;
    double cost = 0.0;
  };
  friend class ProgressiveMeshBuilder;

  std::vector<std::uint32_t> m_indices; // the original triangles
  std::vector<std::uint32_t> m_weld;
  std::vector<std::uint8_t> m_locked;
  int m_lockedCount = 0;
  int m_weldedCount = 0;
  std::size_t m_triangleCount = 0;
  std::vector<Collapse> m_collapses;
  std::vector<std::uint32_t> m_from, m_to;
  std::vector<std::uint32_t> m_pruned;
  std::size_t m_cleanCollapses = 0;
  std::vector<std::size_t> m_trianglesAfter; // [k]: triangles after k collapses, k = 0 .. collapseCount()
};

} // namespace mlod
