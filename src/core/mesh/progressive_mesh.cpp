#include "core/mesh/progressive_mesh.h"

#include "core/cancel.h"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <numeric>
#include <queue>
#include <unordered_map>

namespace mlod {

namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

// ---- Quadrics and costs ------------------------------------------------------------------

// A symmetric 4x4 quadric (Garland & Heckbert): error(p) = p^T A p + 2 b.p + c, with the
// area weight it was built from.
struct Quadric {
  double a00 = 0, a11 = 0, a22 = 0, a10 = 0, a20 = 0, a21 = 0;
  double b0 = 0, b1 = 0, b2 = 0, c = 0;
  double w = 0;
};

void quadricAdd(Quadric& q, const Quadric& r) {
  q.a00 += r.a00, q.a11 += r.a11, q.a22 += r.a22, q.a10 += r.a10, q.a20 += r.a20, q.a21 += r.a21;
  q.b0 += r.b0, q.b1 += r.b1, q.b2 += r.b2, q.c += r.c, q.w += r.w;
}

// The plane n.p = d (n unit) with weight w.
Quadric quadricFromPlane(const glm::dvec3& n, double d, double w) {
  Quadric q;
  q.a00 = w * n.x * n.x, q.a11 = w * n.y * n.y, q.a22 = w * n.z * n.z;
  q.a10 = w * n.y * n.x, q.a20 = w * n.z * n.x, q.a21 = w * n.z * n.y;
  q.b0 = -w * n.x * d, q.b1 = -w * n.y * d, q.b2 = -w * n.z * d;
  q.c = w * d * d;
  q.w = w;
  return q;
}

double quadricError(const Quadric& q, const glm::dvec3& p) {
  const double rx = q.a00 * p.x + q.a10 * p.y + q.a20 * p.z + 2 * q.b0;
  const double ry = q.a10 * p.x + q.a11 * p.y + q.a21 * p.z + 2 * q.b1;
  const double rz = q.a20 * p.x + q.a21 * p.y + q.a22 * p.z + 2 * q.b2;
  return std::fabs(rx * p.x + ry * p.y + rz * p.z + q.c);
}

// The triangle's plane, weighted by the square root of its area (cm), as meshoptimizer 0.18
// weighs it: the error then grows linearly with a part's size, which keeps silhouettes (area
// weights rank a large part's small move above a thin part's large one).
Quadric quadricFromTriangle(const glm::dvec3& p0, const glm::dvec3& p1, const glm::dvec3& p2, double scale) {
  glm::dvec3 n = glm::cross(p1 - p0, p2 - p0);
  const double length = glm::length(n);
  if (!(length > 0.0))
    return {};
  n /= length;
  return quadricFromPlane(n, glm::dot(n, p0), std::sqrt(0.5 * length) * scale);
}

// The plane through the edge p0 p1 perpendicular to its triangle (p2 its third corner),
// weighted by the edge's length (to match the triangles' weight): keeps a border or a seam
// where it is.
Quadric quadricFromEdge(const glm::dvec3& p0, const glm::dvec3& p1, const glm::dvec3& p2, double scale) {
  glm::dvec3 edge = p1 - p0;
  const double length = glm::length(edge);
  if (!(length > 0.0))
    return {};
  edge /= length;
  glm::dvec3 n = (p2 - p0) - edge * glm::dot(p2 - p0, edge);
  const double height = glm::length(n);
  if (!(height > 0.0))
    return {};
  n /= height;
  return quadricFromPlane(n, glm::dot(n, p0), length * scale);
}

// Weight mass that changes joint between two influence sets (0: same bones, same weights; 1:
// no bone in common).
double skinDistance(const glm::u16vec4& ja, const glm::vec4& wa, const glm::u16vec4& jb, const glm::vec4& wb) {
  double common = 0.0;
  for (int i = 0; i < kMaxInfluences; ++i)
    for (int k = 0; k < kMaxInfluences; ++k)
      if (ja[i] == jb[k])
        common += std::min(wa[i], wb[k]);
  return std::max(0.0, 1.0 - common);
}

// The cost of moving u onto v (progressive_mesh.h): u's quadrics (per pose, importance
// scaled) at v's positions, the move and skin terms, per unit of the weight u's quadrics
// gathered (`weightU`, unscaled). `skin`: skinDistance() of the two, 0 on an unskinned mesh.
double collapseCost(std::span<const Quadric> quadricsU, double weightU, std::span<const glm::dvec3> positionsU,
                    std::span<const glm::dvec3> positionsV, double skin, const ProgressiveMeshSettings& settings) {
  double cost = 0.0;
  for (std::size_t p = 0; p < quadricsU.size(); ++p)
    cost += quadricError(quadricsU[p], positionsV[p]);
  const glm::dvec3 edge = positionsV[0] - positionsU[0];
  // note: a collapse whose quadric cost is nil (u on every plane of its fan at v, as on a
  // ridge where mirrored halves meet) still moves the surface by |u - v|: a small weight on
  // that distance ranks short moves first
  cost += (settings.moveWeight + settings.skinWeight * skin) * quadricsU[0].w * glm::dot(edge, edge);
  // note: the sum alone would rank a small part that moves far (an eye, a finger tip) below
  // a large one that moves a little, and the max distance levels are measured by is set by
  // the former; importance scales the quadrics, not the weight, so it still ranks later
  return weightU > 0.0 ? cost / weightU : cost;
}

// ---- Topology: the welded mesh, on OpenMesh ----------------------------------------------

struct WeldedTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d; // the bind pose, cm
  VertexAttributes(OpenMesh::Attributes::Status);
  HalfedgeAttributes(OpenMesh::Attributes::PrevHalfedge);
  EdgeAttributes(OpenMesh::Attributes::Status);
  FaceAttributes(OpenMesh::Attributes::Status);
  VertexTraits {
    std::uint32_t welded = 0;          // the welded vertex (original vertex index) it stands for
    bool locked = false;               // a non-manifold guard: never moves
    std::vector<glm::dvec3> positions; // skinned, per pose ([0] the bind pose), cm
    std::vector<Quadric> quadrics;     // per pose, scaled by importance
    double weight = 0.0;               // the triangle weights its quadrics gathered (bind pose, unscaled)
  };
  HalfedgeTraits {
    std::uint32_t wedge = kNone; // its triangle's corner (original vertex) at its start vertex
  };
  FaceTraits {
    std::uint32_t triangle = 0; // the original triangle
  };
};
using WeldedMesh = OpenMesh::TriMesh_ArrayKernelT<WeldedTraits>;
using VertexHandle = OpenMesh::VertexHandle;
using HalfedgeHandle = OpenMesh::HalfedgeHandle;
using FaceHandle = OpenMesh::FaceHandle;

// Whether triangle t has two corners welded together.
bool degenerate(const std::vector<std::uint32_t>& weld, const std::vector<std::uint32_t>& indices, std::size_t t) {
  const std::uint32_t a = weld[indices[t * 3]], b = weld[indices[t * 3 + 1]], c = weld[indices[t * 3 + 2]];
  return a == b || b == c || c == a;
}

// Union-find over 0 .. n-1 (path halving); a set is named by its lowest member.
struct DisjointSets {
  std::vector<std::uint32_t> parent;
  explicit DisjointSets(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  std::uint32_t find(std::size_t x) {
    while (parent[x] != x)
      x = parent[x] = parent[parent[x]];
    return std::uint32_t(x);
  }
  void unite(std::size_t a, std::size_t b) {
    const std::uint32_t ra = find(a), rb = find(b);
    parent[std::max(ra, rb)] = std::min(ra, rb);
  }
};

// Per vertex: the lowest vertex index with the same position bits and, on a skinned mesh, the
// same influences (corners at one position that a different skin moves apart are not one
// surface point).
std::vector<std::uint32_t> weldVertices(const SkinnedMesh& mesh) {
  std::vector<std::uint32_t> weld(mesh.vertexCount());
  std::map<std::array<std::uint32_t, 3 + 2 * kMaxInfluences>, std::uint32_t> first;
  for (std::size_t v = 0; v < weld.size(); ++v) {
    std::array<std::uint32_t, 3 + 2 * kMaxInfluences> key = {};
    std::memcpy(key.data(), &mesh.positions[v], 3 * sizeof(std::uint32_t));
    if (mesh.skinned()) {
      for (int i = 0; i < kMaxInfluences; ++i)
        key[std::size_t(3 + i)] = mesh.joints[v][i];
      std::memcpy(key.data() + 3 + kMaxInfluences, &mesh.weights[v], kMaxInfluences * sizeof(std::uint32_t));
    }
    weld[v] = first.emplace(key, static_cast<std::uint32_t>(v)).first->second;
  }
  return weld;
}

// The welded mesh of `mesh`: an OpenMesh vertex per fan of a welded vertex (buildTopology()).
struct Topology {
  WeldedMesh mesh;
  std::vector<std::uint32_t> weld;        // per vertex: its welded vertex (weldVertices())
  std::vector<VertexHandle> vertexOf;     // per welded vertex: its first OpenMesh vertex
  std::vector<std::uint32_t> degenerate;  // input triangles with two corners welded together: kept, never in `mesh`
  std::vector<std::uint8_t> lockedWelded; // per welded vertex
};

Topology buildTopology(const SkinnedMesh& mesh) {
  Topology out;
  out.weld = weldVertices(mesh);
  const std::vector<std::uint32_t>& weld = out.weld;
  WeldedMesh& m = out.mesh;
  const std::size_t n = mesh.vertexCount();
  out.vertexOf.resize(n);
  out.lockedWelded.assign(n, 0);
  const auto addVertex = [&](std::uint32_t w) {
    const VertexHandle v =
        m.add_vertex(WeldedMesh::Point(mesh.positions[w].x, mesh.positions[w].y, mesh.positions[w].z));
    m.data(v).welded = w;
    return v;
  };
  for (std::uint32_t v = 0; v < n; ++v)
    if (weld[v] == v)
      out.vertexOf[v] = addVertex(v);
  // A welded vertex's fans: its corners joined through edges that two triangles share in
  // opposite directions and no other uses. Each fan gets a vertex (the first fan the welded one,
  // the others locked copies), so a halfedge vertex has one fan and an edge one triangle a side,
  // and add_face refuses nothing, whatever the triangles' order: the split is the input's alone
  // (fans that meet at a point, an edge of three triangles or of two in one direction).
  const auto next = [](std::uint32_t c) { return c - c % 3 + (c + 1) % 3; };
  std::unordered_map<std::uint64_t, std::pair<std::uint32_t, int>> edges; // welded a -> b: a corner at a, triangles
  edges.reserve(mesh.indices.size());
  for (std::uint32_t c = 0; c < mesh.indices.size(); ++c)
    if (auto& [corner, count] = edges[std::uint64_t(weld[mesh.indices[c]]) << 32 | weld[mesh.indices[next(c)]]];
        !degenerate(weld, mesh.indices, c / 3))
      corner = c, ++count;
  DisjointSets fans(mesh.indices.size());
  for (const auto& [ab, e] : edges)
    if (const auto ba = edges.find(ab << 32 | ab >> 32); e.second == 1 && ba != edges.end() && ba->second.second == 1)
      fans.unite(e.first, next(ba->second.first)), fans.unite(next(e.first), ba->second.first);
  std::vector<VertexHandle> fanVertex(mesh.indices.size()); // per fan (its lowest corner)
  std::vector<std::uint32_t> taken(n, 0);                   // per welded vertex: its fans with a vertex
  for (std::uint32_t t = 0; t < mesh.triangleCount(); ++t) {
    const std::uint32_t* corners = &mesh.indices[std::size_t(t) * 3];
    std::array<VertexHandle, 3> v;
    FaceHandle f;
    if (!degenerate(weld, mesh.indices, t)) {
      for (std::uint32_t k = 0; k < 3; ++k) {
        const std::uint32_t w = weld[corners[k]];
        VertexHandle& fan = fanVertex[fans.find(3 * t + k)];
        if (!fan.is_valid())
          fan = taken[w]++ ? addVertex(w) : out.vertexOf[w];
        v[k] = fan;
        out.lockedWelded[w] |= taken[w] > 1;
      }
      f = m.add_face(v[0], v[1], v[2]);
      assert(f.is_valid()); // one fan a vertex, one triangle an edge side: nothing to refuse
    }
    if (!f.is_valid()) { // degenerate: kept as it is, its vertices locked
      out.degenerate.push_back(t);
      out.lockedWelded[weld[corners[0]]] = out.lockedWelded[weld[corners[1]]] = out.lockedWelded[weld[corners[2]]] = 1;
      continue;
    }
    m.data(f).triangle = t;
    for (const HalfedgeHandle h : m.fh_range(f))
      m.data(h).wedge = corners[std::find(v.begin(), v.end(), m.from_vertex_handle(h)) - v.begin()];
  }
  for (const VertexHandle v : m.vertices())
    m.data(v).locked = out.lockedWelded[m.data(v).welded] != 0;
  return out;
}

// Whether the triangles on either side of `h` lie back to back in the bind pose, their normals
// within 8 degrees of opposite: a fold, where a thin sheet ends (WusonSMD's halves meet along
// its middle in a slit 3e-5 cm wide). The two planes' quadrics let a vertex slide along the
// fold for free, so it keeps its line as a border does (bench_meshlod's notes).
bool folded(const WeldedMesh& m, HalfedgeHandle h) {
  const auto normal = [&](HalfedgeHandle g) {
    const glm::dvec3& a = m.data(m.from_vertex_handle(g)).positions[0];
    const glm::dvec3& b = m.data(m.to_vertex_handle(g)).positions[0];
    return glm::cross(b - a, m.data(m.to_vertex_handle(m.next_halfedge_handle(g))).positions[0] - a);
  };
  const glm::dvec3 n = normal(h), across = normal(m.opposite_halfedge_handle(h));
  return glm::dot(n, across) < -0.99 * glm::length(n) * glm::length(across);
}

// Where each wedge of u goes when u collapses onto v.
struct WedgeMap {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs; // wedge of u -> wedge of v
  bool attribute = false; // a wedge that the edge's triangles do not map moves (an attribute collapse)

  std::uint32_t find(std::uint32_t from) const {
    for (const auto& [a, b] : pairs)
      if (a == from)
        return b;
    return kNone;
  }
};

// The wedge map of the collapse `uv` (u onto v) into out_map; false when there is none: the
// edge's triangles map a wedge two ways (a half-seam), or v has no wedge to take one of u's.
bool mapWedges(const WeldedMesh& m, HalfedgeHandle uv, const SkinnedMesh& mesh, WedgeMap& out_map) {
  out_map.pairs.clear();
  out_map.attribute = false;
  const auto map = [&](std::uint32_t from, std::uint32_t to) {
    const std::uint32_t found = out_map.find(from);
    if (found == kNone)
      out_map.pairs.emplace_back(from, to);
    return found == kNone || found == to;
  };
  // the edge's triangles map u's corner in them onto v's corner in them
  const HalfedgeHandle vu = m.opposite_halfedge_handle(uv);
  if (!m.is_boundary(uv) && !map(m.data(uv).wedge, m.data(m.next_halfedge_handle(uv)).wedge))
    return false;
  if (!m.is_boundary(vu) && !map(m.data(m.next_halfedge_handle(vu)).wedge, m.data(vu).wedge))
    return false;
  // wedges of u on no triangle of the edge: onto v's wedge with the nearest normal, then UV
  for (const HalfedgeHandle h : m.voh_range(m.from_vertex_handle(uv))) {
    const std::uint32_t c = m.data(h).wedge;
    if (m.is_boundary(h) || out_map.find(c) != kNone)
      continue;
    out_map.attribute = true;
    std::uint32_t best = kNone;
    double bestScore = std::numeric_limits<double>::max();
    for (const HalfedgeHandle k : m.voh_range(m.to_vertex_handle(uv))) {
      if (m.is_boundary(k))
        continue;
      const std::uint32_t d = m.data(k).wedge;
      double score = 0.0;
      if (!mesh.normals.empty())
        score += 4.0 * (1.0 - double(glm::dot(mesh.normals[c], mesh.normals[d])));
      if (!mesh.uvs.empty()) {
        const glm::dvec2 delta = glm::dvec2(mesh.uvs[c]) - glm::dvec2(mesh.uvs[d]);
        score += glm::dot(delta, delta);
      }
      // (a NaN score, from a degenerate triangle's normal, must still name a wedge)
      if (best == kNone || score < bestScore)
        bestScore = score, best = d;
    }
    if (best == kNone)
      return false; // v keeps no wedge of its own to take u's: no collapse
    out_map.pairs.emplace_back(c, best);
  }
  return true;
}

// Whether the collapse `uv` with `map` (mapWedges()) turns a triangle that stays over in some
// pose, makes it degenerate in the bind pose, or turns its back on its corners' normals.
bool flips(const WeldedMesh& m, HalfedgeHandle uv, const WedgeMap& map, const SkinnedMesh& mesh) {
  const VertexHandle u = m.from_vertex_handle(uv), v = m.to_vertex_handle(uv);
  const std::vector<glm::dvec3>& pu = m.data(u).positions;
  const std::vector<glm::dvec3>& pv = m.data(v).positions;
  for (const HalfedgeHandle h : m.voh_range(u)) {
    if (m.is_boundary(h))
      continue;
    const HalfedgeHandle next = m.next_halfedge_handle(h), prev = m.next_halfedge_handle(next);
    const VertexHandle a = m.to_vertex_handle(h), b = m.to_vertex_handle(next);
    if (a == v || b == v)
      continue; // the edge's own triangles go away
    const std::vector<glm::dvec3>& pa = m.data(a).positions;
    const std::vector<glm::dvec3>& pb = m.data(b).positions;
    for (std::size_t p = 0; p < pu.size(); ++p) {
      const glm::dvec3 before = glm::cross(pa[p] - pu[p], pb[p] - pu[p]);
      const glm::dvec3 after = glm::cross(pa[p] - pv[p], pb[p] - pv[p]);
      // note: a triangle already degenerate in a pose says nothing about a flip there
      if (glm::length(before) * glm::length(after) > 0.0 && glm::dot(before, after) <= 0.0)
        return true;
      if (p != 0)
        continue;
      if (!(glm::dot(after, after) > 0.0) && glm::dot(before, before) > 0.0)
        return true; // would become degenerate in the bind pose
      if (mesh.normals.empty())
        continue;
      // nor turn its back on its corners' normals (it would shade inside out), unless the
      // input triangle already did
      const std::uint32_t corner = m.data(h).wedge;
      const glm::dvec3 shadingBefore =
          glm::dvec3(mesh.normals[corner] + mesh.normals[m.data(next).wedge] + mesh.normals[m.data(prev).wedge]);
      const glm::dvec3 shadingAfter =
          shadingBefore - glm::dvec3(mesh.normals[corner]) + glm::dvec3(mesh.normals[map.find(corner)]);
      if (glm::dot(after, shadingAfter) < 0.0 && glm::dot(before, shadingBefore) >= 0.0)
        return true;
    }
  }
  return false;
}

// Whether `uv` is the edge of a triangle that stands alone (its three edges open): OpenMesh's
// is_collapse_ok refuses it (the collapse would leave a dangling edge); ours removes the
// triangle.
bool loneTriangle(const WeldedMesh& m, HalfedgeHandle uv) {
  if (m.is_boundary(uv))
    return false;
  for (const HalfedgeHandle h : m.fh_range(m.face_handle(uv)))
    if (!m.is_boundary(m.opposite_halfedge_handle(h)))
      return false;
  return true;
}

// Collapses `uv` (OpenMesh's collapse(): u goes, v stays) and gives u's triangles v's wedges
// by `map`.
void collapseWithWedges(WeldedMesh& m, HalfedgeHandle uv, const WedgeMap& map) {
  if (loneTriangle(m, uv)) {
    m.delete_face(m.face_handle(uv), true);
    return;
  }
  const VertexHandle u = m.from_vertex_handle(uv), v = m.to_vertex_handle(uv);
  // note: where collapse() merges the two halfedges of a side of a removed triangle, it may
  // keep the removed triangle's, whose wedge is that triangle's corner, not the neighbour's;
  // so the corners of u's remaining triangles are noted before and written back after
  struct Corners {
    FaceHandle face;
    std::array<std::pair<VertexHandle, std::uint32_t>, 3> corners; // start vertex, wedge
  };
  std::vector<Corners> faces;
  for (const HalfedgeHandle h : m.voh_range(u)) {
    if (m.is_boundary(h) || m.to_vertex_handle(h) == v || m.to_vertex_handle(m.next_halfedge_handle(h)) == v)
      continue;
    Corners& f = faces.emplace_back();
    f.face = m.face_handle(h);
    int k = 0;
    for (const HalfedgeHandle g : m.fh_range(f.face)) {
      const VertexHandle from = m.from_vertex_handle(g);
      f.corners[k++] = from == u ? std::pair(v, map.find(m.data(g).wedge)) : std::pair(from, m.data(g).wedge);
    }
  }
  m.collapse(uv);
  for (const Corners& f : faces)
    for (const HalfedgeHandle g : m.fh_range(f.face)) {
      const VertexHandle from = m.from_vertex_handle(g);
      m.data(g).wedge =
          std::find_if(f.corners.begin(), f.corners.end(), [&](const auto& c) { return c.first == from; })->second;
    }
}

// ---- The queue driver ----------------------------------------------------------------------

// HeapEntry::target of a component's pruning (HeapEntry::vertex is then the component).
constexpr std::uint32_t kPrune = kNone - 1;

struct HeapEntry {
  double cost;
  std::uint32_t vertex;
  std::uint32_t target;
  std::uint32_t version;
  bool attribute;                                // an attribute collapse or a pruning
  bool operator<(const HeapEntry& other) const { // std::priority_queue pops the largest
    return cost > other.cost;                    // the cheapest first, whatever its kind
  }
};

} // namespace

// Builds the collapse order: the queue of a simplification in progress over the welded mesh.
class ProgressiveMeshBuilder {
public:
  ProgressiveMeshBuilder(const SkinnedMesh& mesh, std::span<const std::vector<glm::vec3>> poses,
                         std::span<const float> importance, const ProgressiveMeshSettings& settings,
                         ProgressiveMesh& out);

  void run(const std::atomic<bool>* cancel);

private:
  void accumulateQuadrics(std::span<const std::vector<glm::vec3>> poses, std::span<const float> importance);
  // Ranks u again: its cheapest allowed collapse goes on the heap (none for a locked or gone u).
  void push(VertexHandle u);
  void collapse(VertexHandle u, VertexHandle v, double cost, bool attribute);
  // Connected components (over welded vertices) and what pruning each costs.
  void findComponents();
  // Removes component c's live triangles as one step; false when it may not go (the last
  // component with triangles).
  bool prune(std::uint32_t c, double cost);

  const SkinnedMesh& m_mesh;
  const ProgressiveMeshSettings& m_settings;
  ProgressiveMesh& m_out;
  Topology m_topology;
  WeldedMesh& m_m; // m_topology.mesh
  std::size_t m_poseCount;
  std::vector<std::uint32_t> m_version; // per vertex of m_m
  std::priority_queue<HeapEntry> m_heap;
  std::size_t m_triangles = 0;
  // Per vertex of m_m its component (kNone where no triangle uses it); per component its
  // vertices, live triangles, pruning cost, and whether it may go.
  struct Component {
    std::vector<VertexHandle> vertices;
    std::size_t triangles = 0;
    double pruneCost = 0.0;
    bool prunable = true;
  };
  std::vector<std::uint32_t> m_component;
  std::vector<Component> m_components;
  std::size_t m_liveComponents = 0;
  bool m_sawAttribute = false;
};

ProgressiveMeshBuilder::ProgressiveMeshBuilder(const SkinnedMesh& mesh, std::span<const std::vector<glm::vec3>> poses,
                                               std::span<const float> importance,
                                               const ProgressiveMeshSettings& settings, ProgressiveMesh& out)
    : m_mesh(mesh), m_settings(settings), m_out(out), m_topology(buildTopology(mesh)), m_m(m_topology.mesh),
      m_poseCount(poses.size()), m_triangles(mesh.triangleCount()) {
  m_out.m_indices = mesh.indices;
  m_out.m_triangleCount = mesh.triangleCount();
  m_out.m_weld = m_topology.weld;
  m_out.m_locked.resize(mesh.vertexCount());
  m_out.m_weldedCount = m_out.m_lockedCount = 0;
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    const std::uint32_t w = m_out.m_weld[v];
    m_out.m_locked[v] = m_topology.lockedWelded[w];
    m_out.m_weldedCount += w == v;
    m_out.m_lockedCount += w == v && m_topology.lockedWelded[w];
  }
  m_version.assign(m_m.n_vertices(), 0);
  accumulateQuadrics(poses, importance);
  findComponents();
}

void ProgressiveMeshBuilder::accumulateQuadrics(std::span<const std::vector<glm::vec3>> poses,
                                                std::span<const float> importance) {
  std::vector<double> scale(m_mesh.vertexCount(), 0.0); // per welded vertex: the largest importance of its wedges
  for (std::size_t v = 0; v < m_mesh.vertexCount(); ++v) {
    double& s = scale[m_out.m_weld[v]];
    s = std::max(s, importance.empty() ? 1.0 : double(importance[v]));
  }
  for (const VertexHandle v : m_m.vertices()) {
    auto& data = m_m.data(v);
    data.positions.resize(m_poseCount);
    for (std::size_t p = 0; p < m_poseCount; ++p)
      data.positions[p] = glm::dvec3(poses[p][data.welded]);
    data.quadrics.assign(m_poseCount, Quadric{});
  }
  for (const FaceHandle f : m_m.faces()) {
    const HalfedgeHandle h0 = m_m.halfedge_handle(f);
    const std::array<HalfedgeHandle, 3> h = {h0, m_m.next_halfedge_handle(h0), m_m.prev_halfedge_handle(h0)};
    const std::array<VertexHandle, 3> v = {m_m.from_vertex_handle(h[0]), m_m.from_vertex_handle(h[1]),
                                           m_m.from_vertex_handle(h[2])};
    const auto position = [&](int k, std::size_t p) -> const glm::dvec3& { return m_m.data(v[k]).positions[p]; };
    for (std::size_t p = 0; p < m_poseCount; ++p)
      for (int k = 0; k < 3; ++k)
        quadricAdd(m_m.data(v[k]).quadrics[p],
                   quadricFromTriangle(position(0, p), position(1, p), position(2, p), scale[m_m.data(v[k]).welded]));
    const double area = 0.5 * glm::length(glm::cross(position(1, 0) - position(0, 0), position(2, 0) - position(0, 0)));
    for (int k = 0; k < 3; ++k)
      m_m.data(v[k]).weight += std::sqrt(area);
    // edge quadrics: open borders and folds, and seams (the triangle across meets this one in
    // other wedges)
    for (int k = 0; k < 3; ++k) {
      const HalfedgeHandle across = m_m.opposite_halfedge_handle(h[k]);
      double weight = 0.0;
      if (m_m.is_boundary(across) || folded(m_m, h[k]))
        weight = m_settings.borderWeight;
      else if (m_m.data(across).wedge != m_m.data(h[(k + 1) % 3]).wedge ||
               m_m.data(m_m.next_halfedge_handle(across)).wedge != m_m.data(h[k]).wedge)
        weight = m_settings.seamWeight;
      if (!(weight > 0.0))
        continue;
      for (const int end : {k, (k + 1) % 3})
        for (std::size_t p = 0; p < m_poseCount; ++p)
          quadricAdd(m_m.data(v[end]).quadrics[p],
                     quadricFromEdge(position(k, p), position((k + 1) % 3, p), position((k + 2) % 3, p),
                                     weight * scale[m_m.data(v[end]).welded]));
    }
  }
}

void ProgressiveMeshBuilder::findComponents() {
  const std::size_t n = m_m.n_vertices();
  DisjointSets sets(n);
  // per triangle its vertices, the degenerate ones (outside m_m) last; a copy joins its welded
  // vertex's component
  std::vector<std::array<VertexHandle, 3>> triangles;
  for (const FaceHandle f : m_m.faces())
    std::copy(m_m.fv_begin(f), m_m.fv_end(f), triangles.emplace_back().begin());
  for (std::uint32_t t : m_topology.degenerate)
    for (std::array<VertexHandle, 3>& corners = triangles.emplace_back(); int k : {0, 1, 2})
      corners[k] = m_topology.vertexOf[m_out.m_weld[m_mesh.indices[t * 3 + std::size_t(k)]]];
  for (const auto& t : triangles)
    sets.unite(t[0].idx(), t[1].idx()), sets.unite(t[0].idx(), t[2].idx());
  for (const VertexHandle v : m_m.vertices())
    sets.unite(v.idx(), m_topology.vertexOf[m_m.data(v).welded].idx());
  m_component.assign(n, kNone);
  std::vector<std::uint32_t> index(n, kNone); // per root: its component
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const std::uint32_t root = sets.find(triangles[t][0].idx());
    if (index[root] == kNone) {
      index[root] = static_cast<std::uint32_t>(m_components.size());
      m_components.emplace_back();
    }
    Component& component = m_components[index[root]];
    ++component.triangles;
    component.prunable &= t < m_m.n_faces(); // a degenerate triangle is never pruned
    for (const VertexHandle v : triangles[t])
      if (m_component[std::size_t(v.idx())] == kNone) {
        m_component[std::size_t(v.idx())] = index[root];
        component.vertices.push_back(v);
        component.prunable &= !m_m.data(v).locked;
      }
  }
  m_liveComponents = m_components.size();
  // note: pruning a component moves each of its vertices by about its radius in every pose,
  // so it costs what collapsing them that far would in the same metric: sum over poses of
  // (the area weight of its quadrics) x (its radius in that pose)^2. Collapses inside a
  // component only merge its quadrics, so the cost holds whenever it is popped
  for (Component& component : m_components) {
    if (!component.prunable || m_components.size() < 2)
      continue;
    for (std::size_t p = 0; p < m_poseCount; ++p) {
      glm::dvec3 centre(0.0);
      double weight = 0.0;
      for (const VertexHandle v : component.vertices) {
        centre += m_m.data(v).positions[p];
        weight += m_m.data(v).quadrics[p].w;
      }
      centre /= double(component.vertices.size());
      double radius2 = 0.0;
      for (const VertexHandle v : component.vertices) {
        const glm::dvec3 d = m_m.data(v).positions[p] - centre;
        radius2 = std::max(radius2, glm::dot(d, d));
      }
      component.pruneCost += weight * radius2;
    }
    double total = 0.0; // collapse costs are per unit of weight (collapseCost()): so is this one
    for (const VertexHandle v : component.vertices)
      total += m_m.data(v).weight;
    if (total > 0.0)
      component.pruneCost /= total;
  }
}

bool ProgressiveMeshBuilder::prune(std::uint32_t c, double cost) {
  Component& component = m_components[c];
  if (component.triangles == 0 || m_liveComponents < 2)
    return false;
  ProgressiveMesh::Collapse record;
  record.firstWedge = static_cast<std::uint32_t>(m_out.m_from.size());
  record.firstPruned = static_cast<std::uint32_t>(m_out.m_pruned.size());
  record.cost = cost;
  std::vector<FaceHandle> faces;
  for (const VertexHandle v : component.vertices) {
    if (m_m.status(v).deleted())
      continue;
    faces.assign(m_m.vf_begin(v), m_m.vf_end(v));
    for (const FaceHandle f : faces) {
      m_out.m_pruned.push_back(m_m.data(f).triangle);
      m_m.delete_face(f, true);
      --m_triangles;
    }
    m_m.status(v).set_deleted(true);
    ++m_version[std::size_t(v.idx())];
  }
  record.prunedCount = static_cast<std::uint32_t>(m_out.m_pruned.size() - record.firstPruned);
  component.triangles = 0;
  --m_liveComponents;
  m_out.m_collapses.push_back(record);
  m_out.m_trianglesAfter.push_back(m_triangles);
  return true;
}

void ProgressiveMeshBuilder::push(VertexHandle u) {
  const std::uint32_t version = ++m_version[std::size_t(u.idx())];
  const auto& data = m_m.data(u);
  if (data.locked || m_m.status(u).deleted() || m_m.is_isolated(u))
    return;
  const bool border = m_m.is_boundary(u);
  std::vector<std::pair<double, HalfedgeHandle>> options; // cost, u -> v
  for (const HalfedgeHandle h : m_m.voh_range(u)) {
    if (border && !m_m.is_boundary(m_m.edge_handle(h)))
      continue; // a border vertex moves only along its border
    const auto& target = m_m.data(m_m.to_vertex_handle(h));
    const double skin = m_mesh.skinned() && m_settings.skinWeight > 0.0
                            ? skinDistance(m_mesh.joints[data.welded], m_mesh.weights[data.welded],
                                           m_mesh.joints[target.welded], m_mesh.weights[target.welded])
                            : 0.0;
    options.emplace_back(collapseCost(data.quadrics, data.weight, data.positions, target.positions, skin, m_settings),
                         h);
  }
  std::sort(options.begin(), options.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  // the cheapest allowed collapse: a seam is a cost (its edge quadrics), not a second tier
  // after every clean collapse (that left cheap seam collapses behind costly clean ones)
  WedgeMap map;
  for (const auto& [cost, h] : options)
    if (mapWedges(m_m, h, m_mesh, map) && (m_m.is_collapse_ok(h) || loneTriangle(m_m, h)) &&
        !flips(m_m, h, map, m_mesh)) {
      m_heap.push(HeapEntry{cost, std::uint32_t(u.idx()), std::uint32_t(m_m.to_vertex_handle(h).idx()), version,
                            map.attribute});
      return;
    }
}

void ProgressiveMeshBuilder::collapse(VertexHandle u, VertexHandle v, double cost, bool attribute) {
  const HalfedgeHandle uv = m_m.find_halfedge(u, v);
  WedgeMap map;
  // ranked legal; a map that cannot be made now (damaged input: ../shared/repro/crash_segv_min.obj
  // mapped a corner to no wedge and crashed) leaves the mesh as it is
  if (!uv.is_valid() || !mapWedges(m_m, uv, m_mesh, map) || !(m_m.is_collapse_ok(uv) || loneTriangle(m_m, uv)))
    return;
  assert(map.attribute == attribute);
  (void)attribute;
  ProgressiveMesh::Collapse record;
  record.firstWedge = static_cast<std::uint32_t>(m_out.m_from.size());
  record.wedgeCount = static_cast<std::uint32_t>(map.pairs.size());
  record.cost = cost;
  for (const auto& [from, to] : map.pairs) {
    m_out.m_from.push_back(from);
    m_out.m_to.push_back(to);
  }
  for (const HalfedgeHandle h : {uv, m_m.opposite_halfedge_handle(uv)})
    if (!m_m.is_boundary(h)) {
      --m_triangles;
      if (--m_components[m_component[std::size_t(u.idx())]].triangles == 0)
        --m_liveComponents;
    }
  collapseWithWedges(m_m, uv, map);
  auto& from = m_m.data(u);
  auto& to = m_m.data(v);
  for (std::size_t p = 0; p < to.quadrics.size(); ++p)
    quadricAdd(to.quadrics[p], from.quadrics[p]);
  to.weight += from.weight;
  m_out.m_collapses.push_back(record);
  m_out.m_trianglesAfter.push_back(m_triangles);
  // v and its neighbours see a new fan: rank them again
  push(v);
  for (const VertexHandle w : m_m.vv_range(v))
    push(w);
}

void ProgressiveMeshBuilder::run(const std::atomic<bool>* cancel) {
  m_out.m_trianglesAfter.assign(1, m_triangles);
  m_out.m_cleanCollapses = 0;
  for (const VertexHandle v : m_m.vertices())
    push(v);
  for (std::uint32_t c = 0; c < m_components.size(); ++c)
    if (m_components[c].prunable && m_components.size() > 1)
      m_heap.push(HeapEntry{m_components[c].pruneCost, c, kPrune, 0, true});
  // note: a few hundred collapses take well under a millisecond, so the flag is looked at
  // that often at no measurable cost
  constexpr std::size_t kCancelCheckEvery = 256;
  for (std::size_t popped = 0; !m_heap.empty(); ++popped) {
    if (popped % kCancelCheckEvery == 0 && cancelled(cancel))
      return;
    const HeapEntry top = m_heap.top();
    m_heap.pop();
    if (top.target == kPrune) {
      if (!m_sawAttribute && m_components[top.vertex].triangles > 0 && m_liveComponents > 1) {
        m_out.m_cleanCollapses = m_out.m_collapses.size();
        m_sawAttribute = true;
      }
      prune(top.vertex, top.cost);
      continue;
    }
    // note: an entry is current while its vertex's version is: every collapse ranks again
    // the vertices whose fan, neighbours or wedges it changed, which is all a candidate's
    // cost and validity depend on (positions never move)
    const VertexHandle u(int(top.vertex)), v(int(top.target));
    if (top.version != m_version[top.vertex] || m_m.status(u).deleted() || m_m.status(v).deleted())
      continue;
    if (top.attribute && !m_sawAttribute) {
      m_out.m_cleanCollapses = m_out.m_collapses.size();
      m_sawAttribute = true;
    }
    collapse(u, v, top.cost, top.attribute);
  }
  if (!m_sawAttribute)
    m_out.m_cleanCollapses = m_out.m_collapses.size();
}

ProgressiveMesh ProgressiveMesh::build(const SkinnedMesh& mesh, std::span<const std::vector<glm::vec3>> poses,
                                       std::span<const float> vertexImportance, const ProgressiveMeshSettings& settings,
                                       const std::atomic<bool>* cancel) {
  assert(!poses.empty());
  assert(vertexImportance.empty() || vertexImportance.size() == mesh.vertexCount());
  ProgressiveMesh out;
  ProgressiveMeshBuilder builder(mesh, poses, vertexImportance, settings, out);
  builder.run(cancel);
  return out;
}

std::size_t ProgressiveMesh::collapsesFor(std::size_t triangles) const {
  // m_trianglesAfter never rises
  const auto found = std::find_if(m_trianglesAfter.begin(), m_trianglesAfter.end(),
                                  [&](std::size_t count) { return count <= triangles; });
  return found == m_trianglesAfter.end() ? collapseCount() : static_cast<std::size_t>(found - m_trianglesAfter.begin());
}

MeshLevelIndices ProgressiveMesh::level(std::size_t collapses) const {
  assert(collapses <= collapseCount());
  const std::size_t n = m_weld.size();
  std::vector<std::uint32_t> remap(n);
  for (std::size_t v = 0; v < n; ++v)
    remap[v] = static_cast<std::uint32_t>(v);
  std::vector<std::uint8_t> pruned(m_triangleCount, 0);
  for (std::size_t k = 0; k < collapses; ++k) {
    const Collapse& c = m_collapses[k];
    for (std::uint32_t i = c.firstWedge; i < c.firstWedge + c.wedgeCount; ++i)
      remap[m_from[i]] = m_to[i];
    for (std::uint32_t i = c.firstPruned; i < c.firstPruned + c.prunedCount; ++i)
      pruned[m_pruned[i]] = 1;
  }
  // a wedge's target may have collapsed later: follow to the end (collapses only ever move a
  // wedge onto a live one, so every chain ends)
  for (std::size_t v = 0; v < n; ++v) {
    std::uint32_t r = remap[v];
    while (remap[r] != r)
      r = remap[r];
    remap[v] = r;
  }
  MeshLevelIndices out;
  out.indices.reserve(m_trianglesAfter[collapses] * 3);
  out.triangles.reserve(m_trianglesAfter[collapses]);
  for (std::size_t t = 0; t < m_triangleCount; ++t) {
    if (pruned[t])
      continue;
    const std::uint32_t a = remap[m_indices[t * 3]], b = remap[m_indices[t * 3 + 1]], c = remap[m_indices[t * 3 + 2]];
    const std::uint32_t wa = m_weld[a], wb = m_weld[b], wc = m_weld[c];
    if (!degenerate(m_weld, m_indices, t) && (wa == wb || wb == wc || wc == wa))
      continue;
    out.indices.insert(out.indices.end(), {a, b, c});
    out.triangles.push_back(static_cast<std::uint32_t>(t));
  }
  assert(out.triangles.size() == m_trianglesAfter[collapses]);
  return out;
}

} // namespace mlod
