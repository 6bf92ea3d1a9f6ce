#include "core/mesh/progressive_mesh.h"

#include "core/mesh/surface_distance.h"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModAspectRatioT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModProgMeshT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <limits>
#include <mutex>
#include <unordered_map>

namespace mlod {

namespace {

struct DecimationTraits : OpenMesh::DefaultTraits {
  VertexAttributes(OpenMesh::Attributes::Status);
  EdgeAttributes(OpenMesh::Attributes::Status);
  HalfedgeAttributes(OpenMesh::Attributes::PrevHalfedge);
  FaceAttributes(OpenMesh::Attributes::Status | OpenMesh::Attributes::Normal);
};
using DecimationMesh = OpenMesh::TriMesh_ArrayKernelT<DecimationTraits>;
using Decimater = OpenMesh::Decimater::DecimaterT<DecimationMesh>;
using CollapseInfo = OpenMesh::Decimater::CollapseInfoT<DecimationMesh>;
using QuadricModule = OpenMesh::Decimater::ModQuadricT<DecimationMesh>;

// The corners of one segment's faces: which OpenMesh vertex and which wedge (original
// vertex) each holds, by face index. OpenMesh moves halfedges between faces when it
// collapses, so corners are kept here rather than in halfedge properties.
struct Corners {
  std::vector<std::array<int, 3>> vertex;
  std::vector<std::array<std::uint32_t, 3>> wedge;

  std::uint32_t wedgeAt(OpenMesh::FaceHandle face, OpenMesh::VertexHandle v) const {
    const auto f = static_cast<std::size_t>(face.idx());
    for (std::size_t k = 0; k < 3; ++k)
      if (vertex[f][k] == v.idx())
        return wedge[f][k];
    assert(false && "vertex not in face");
    return wedge[f][0];
  }
};

// What one collapse does to wedges, and what it costs.
struct WedgePlan {
  std::uint32_t from[2] = {0, 0};
  std::uint32_t to[2] = {0, 0};
  std::uint8_t wedges = 0;
};

struct Record {
  WedgePlan plan;
  std::uint8_t removedTriangles = 0;
  double distanceCm = 0.0; // the farthest removed vertex from the surface right after it
};

// A binary module: allows a collapse only where every corner of v0 has one clear wedge of
// v1 to become (see progressive_mesh.h); after each collapse it rewrites the corners and
// records the wedge mapping and the error estimate.
template <class MeshT>
class ModWedgeT : public OpenMesh::Decimater::ModBaseT<MeshT> {
public:
  DECIMATING_MODULE(ModWedgeT, MeshT, Wedge);

  explicit ModWedgeT(MeshT& mesh) : Base(mesh, true) {}

  // `normals`: per wedge (original vertex), the direction the surface faces there.
  void setup(Corners* corners, const std::vector<glm::vec3>* normals, const TriangleTree* original,
             std::vector<Record>* out_records) {
    m_corners = corners;
    m_original = original;
    m_normals = normals;
    m_facePoints.assign(corners->vertex.size(), {});
    m_records = out_records;
  }

  float collapse_priority(const CollapseInfo& ci) override {
    WedgePlan plan;
    return this->planCollapse(ci, plan) ? float(Base::LEGAL_COLLAPSE) : float(Base::ILLEGAL_COLLAPSE);
  }

  void preprocess_collapse(const CollapseInfo& ci) override {
    m_pending = Record{};
    [[maybe_unused]] const bool legal = this->planCollapse(ci, m_pending.plan);
    assert(legal); // the one-ring of a collapse is re-examined after it, so a legal plan stays legal
    m_pending.removedTriangles = static_cast<std::uint8_t>(int(ci.fl.is_valid()) + int(ci.fr.is_valid()));
  }

  void postprocess_collapse(const CollapseInfo& ci) override {
    MeshT& mesh = Base::mesh();
    const int v0 = ci.v0.idx();
    for (auto face : mesh.vf_range(ci.v1)) {
      const auto f = static_cast<std::size_t>(face.idx());
      for (std::size_t k = 0; k < 3; ++k) {
        if (m_corners->vertex[f][k] != v0)
          continue;
        m_corners->vertex[f][k] = ci.v1.idx();
        std::uint32_t& wedge = m_corners->wedge[f][k];
        for (int i = 0; i < m_pending.plan.wedges; ++i)
          if (wedge == m_pending.plan.from[i]) {
            wedge = m_pending.plan.to[i];
            break;
          }
      }
    }
    m_pending.distanceCm = std::max(redistributePoints(ci), distanceFromOriginal(ci));
    m_records->push_back(m_pending);
  }

private:
  bool planCollapse(const CollapseInfo& ci, WedgePlan& out_plan) {
    if (!ci.fl.is_valid() || !ci.fr.is_valid())
      return false; // v0 on a border: such vertices are locked anyway
    const Corners& corners = *m_corners;
    const std::uint32_t left0 = corners.wedgeAt(ci.fl, ci.v0), right0 = corners.wedgeAt(ci.fr, ci.v0);
    const std::uint32_t left1 = corners.wedgeAt(ci.fl, ci.v1), right1 = corners.wedgeAt(ci.fr, ci.v1);
    // seam edges at v0: changes of v0's wedge between consecutive faces around it
    int changes = 0;
    std::uint32_t first = 0, previous = 0;
    bool any = false;
    for (auto face : Base::mesh().vf_range(ci.v0)) {
      const std::uint32_t wedge = corners.wedgeAt(face, ci.v0);
      if (!any)
        first = wedge;
      else if (wedge != previous)
        ++changes;
      previous = wedge;
      any = true;
    }
    if (any && previous != first)
      ++changes;
    if (changes == 0) {
      if (left1 != right1)
        return false; // v1's corners beside the edge differ: v0's corners would have no single wedge
      out_plan.wedges = 1;
      out_plan.from[0] = left0;
      out_plan.to[0] = left1;
      return keepsOrientation(ci, out_plan);
    }
    if (changes == 2 && left0 != right0 && left1 != right1) { // along the seam, each side onto its side
      out_plan.wedges = 2;
      out_plan.from[0] = left0;
      out_plan.to[0] = left1;
      out_plan.from[1] = right0;
      out_plan.to[1] = right1;
      return keepsOrientation(ci, out_plan);
    }
    return false;
  }

  // Every face the collapse reshapes keeps a real area and faces the way its corners'
  // original normals say. ModNormalFlipping bounds the turn of one collapse; this bounds
  // the sum of them, so no sequence of collapses turns a triangle inside out.
  bool keepsOrientation(const CollapseInfo& ci, const WedgePlan& plan) {
    MeshT& mesh = Base::mesh();
    for (auto face : mesh.vf_range(ci.v0)) {
      if (face == ci.fl || face == ci.fr)
        continue;
      const auto f = static_cast<std::size_t>(face.idx());
      glm::dvec3 p[3];
      glm::dvec3 shading(0.0);
      for (std::size_t k = 0; k < 3; ++k) {
        std::uint32_t wedge = m_corners->wedge[f][k];
        if (m_corners->vertex[f][k] == ci.v0.idx()) {
          p[k] = glm::dvec3(ci.p1[0], ci.p1[1], ci.p1[2]);
          for (int i = 0; i < plan.wedges; ++i)
            if (wedge == plan.from[i])
              wedge = plan.to[i];
        } else {
          const auto& q = mesh.point(OpenMesh::VertexHandle(m_corners->vertex[f][k]));
          p[k] = glm::dvec3(q[0], q[1], q[2]);
        }
        shading += glm::dvec3((*m_normals)[wedge]);
      }
      const glm::dvec3 n = glm::cross(p[1] - p[0], p[2] - p[0]);
      const double longest = std::max({glm::dot(p[1] - p[0], p[1] - p[0]), glm::dot(p[2] - p[1], p[2] - p[1]),
                                       glm::dot(p[0] - p[2], p[0] - p[2])});
      if (!(glm::length(n) > 1e-6 * longest)) // a sliver of no area
        return false;
      if (!(glm::dot(n, shading) > 0.0))
        return false;
    }
    return true;
  }

  // As OpenMesh's ModHausdorff: every removed vertex stays attached to the face nearest to
  // it; after a collapse the points of the faces around v1 (and of the two removed faces,
  // and v0 itself) go to their nearest face around v1. Returns the largest of those
  // distances (cm): how far the collapse leaves the original vertices from the surface.
  double redistributePoints(const CollapseInfo& ci) {
    MeshT& mesh = Base::mesh();
    m_faces.clear();
    m_points.clear();
    const auto take = [&](OpenMesh::FaceHandle face) {
      std::vector<glm::dvec3>& points = m_facePoints[static_cast<std::size_t>(face.idx())];
      m_points.insert(m_points.end(), points.begin(), points.end());
      points.clear();
    };
    for (auto face : mesh.vf_range(ci.v1)) {
      m_faces.push_back(face);
      take(face);
    }
    take(ci.fl);
    take(ci.fr);
    m_points.emplace_back(ci.p0[0], ci.p0[1], ci.p0[2]);
    double worst = 0.0;
    if (m_faces.empty())
      return 0.0;
    for (const glm::dvec3& point : m_points) {
      double nearest = std::numeric_limits<double>::infinity();
      OpenMesh::FaceHandle nearestFace = m_faces.front();
      for (OpenMesh::FaceHandle face : m_faces) {
        auto fv = mesh.cfv_iter(face);
        const auto& a = mesh.point(*fv);
        const auto& b = mesh.point(*(++fv));
        const auto& c = mesh.point(*(++fv));
        const double d = pointTriangleDistanceSquared(point, glm::dvec3(a[0], a[1], a[2]), glm::dvec3(b[0], b[1], b[2]),
                                                      glm::dvec3(c[0], c[1], c[2]));
        if (d < nearest) {
          nearest = d;
          nearestFace = face;
        }
      }
      m_facePoints[static_cast<std::size_t>(nearestFace.idx())].push_back(point);
      worst = std::max(worst, nearest);
    }
    return std::sqrt(worst);
  }

  // The other way round: how far the faces around v1 stray from the segment's original
  // surface, at their centroids and edge midpoints (cm).
  double distanceFromOriginal(const CollapseInfo& ci) {
    MeshT& mesh = Base::mesh();
    double worst = 0.0;
    for (auto face : mesh.vf_range(ci.v1)) {
      auto fv = mesh.cfv_iter(face);
      glm::dvec3 p[3];
      for (int k = 0; k < 3; ++k, ++fv) {
        const auto& q = mesh.point(*fv);
        p[k] = glm::dvec3(q[0], q[1], q[2]);
      }
      const glm::dvec3 samples[4] = {(p[0] + p[1] + p[2]) / 3.0, 0.5 * (p[0] + p[1]), 0.5 * (p[1] + p[2]),
                                     0.5 * (p[2] + p[0])};
      for (const glm::dvec3& sample : samples)
        if (!m_original->anyWithin(sample, worst, &m_hint))
          worst = m_original->nearestSquared(sample, std::numeric_limits<double>::infinity(), &m_hint);
    }
    return std::sqrt(worst);
  }

  Corners* m_corners = nullptr;
  const TriangleTree* m_original = nullptr;
  int m_hint = -1;
  const std::vector<glm::vec3>* m_normals = nullptr;
  std::vector<std::vector<glm::dvec3>> m_facePoints; // per face: the removed vertices nearest to it
  std::vector<OpenMesh::FaceHandle> m_faces;
  std::vector<glm::dvec3> m_points;
  std::vector<Record>* m_records = nullptr;
  Record m_pending;
};

using WedgeModule = ModWedgeT<DecimationMesh>;

void silenceOpenMeshOnce() {
  // note: OpenMesh reports faces it cannot add on its error stream; they are handled here
  // (kept as they are, their vertices locked), so the stream stays quiet.
  static std::once_flag once;
  std::call_once(once, [] { omerr().disable(); });
}

// Per vertex, the area-weighted normal of the faces around its welded vertex: the
// orientation guard's reference for a mesh without normals.
std::vector<glm::vec3> faceWeightedNormals(const SkinnedMesh& mesh, const MeshSegmentation& segmentation) {
  std::vector<glm::vec3> sums(mesh.vertexCount(), glm::vec3(0.0f));
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const glm::vec3 a = mesh.positions[mesh.indices[t * 3]], b = mesh.positions[mesh.indices[t * 3 + 1]],
                    c = mesh.positions[mesh.indices[t * 3 + 2]];
    const glm::vec3 n = glm::cross(b - a, c - a);
    for (std::size_t k = 0; k < 3; ++k)
      sums[segmentation.weld[mesh.indices[t * 3 + k]]] += n;
  }
  std::vector<glm::vec3> out(mesh.vertexCount());
  for (std::size_t v = 0; v < out.size(); ++v)
    out[v] = sums[segmentation.weld[v]];
  return out;
}

struct SegmentResult {
  std::vector<Record> records;
  std::vector<std::uint32_t> newlyLocked; // welded vertices of triangles OpenMesh could not hold
};

SegmentResult decimateSegment(const std::vector<std::uint32_t>& indices, const MeshSegmentation& segmentation,
                              const MeshSegment& segment, const std::vector<glm::vec3>& positions,
                              const std::vector<glm::vec3>& normals, const ProgressiveMeshSettings& settings) {
  SegmentResult result;
  DecimationMesh mesh;
  Corners corners;
  std::unordered_map<std::uint32_t, OpenMesh::VertexHandle> handles; // welded vertex -> OpenMesh vertex
  handles.reserve(segment.triangles.size() * 2);
  const auto handleOf = [&](std::uint32_t welded) {
    auto [it, inserted] = handles.try_emplace(welded);
    if (inserted) {
      const glm::vec3& p = positions[welded];
      it->second = mesh.add_vertex(DecimationMesh::Point(p.x, p.y, p.z));
      if (segmentation.locked[welded])
        mesh.status(it->second).set_locked(true);
    }
    return it->second;
  };
  std::vector<std::uint32_t> failed;
  for (std::uint32_t t : segment.triangles) {
    std::array<std::uint32_t, 3> wedge{};
    std::array<OpenMesh::VertexHandle, 3> v;
    for (std::size_t k = 0; k < 3; ++k) {
      wedge[k] = indices[std::size_t(t) * 3 + k];
      v[k] = handleOf(segmentation.weld[wedge[k]]);
    }
    OpenMesh::FaceHandle face;
    if (v[0] != v[1] && v[1] != v[2] && v[0] != v[2])
      face = mesh.add_face(v[0], v[1], v[2]);
    if (!face.is_valid()) {
      failed.push_back(t);
      continue;
    }
    assert(static_cast<std::size_t>(face.idx()) == corners.vertex.size());
    corners.vertex.push_back({v[0].idx(), v[1].idx(), v[2].idx()});
    corners.wedge.push_back(wedge);
  }
  for (std::uint32_t t : failed)
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint32_t welded = segmentation.weld[indices[std::size_t(t) * 3 + k]];
      mesh.status(handleOf(welded)).set_locked(true);
      if (!segmentation.locked[welded])
        result.newlyLocked.push_back(welded);
    }
  if (mesh.n_faces() == 0)
    return result;
  mesh.update_face_normals();

  Decimater decimater(mesh);
  QuadricModule::Handle quadric;
  OpenMesh::Decimater::ModNormalFlippingT<DecimationMesh>::Handle normalFlipping;
  OpenMesh::Decimater::ModAspectRatioT<DecimationMesh>::Handle aspectRatio;
  OpenMesh::Decimater::ModProgMeshT<DecimationMesh>::Handle progMesh;
  WedgeModule::Handle wedges;
  decimater.add(quadric);
  decimater.module(quadric).unset_max_err();
  decimater.add(normalFlipping);
  decimater.module(normalFlipping).set_max_normal_deviation(settings.maxNormalDeviationDegrees);
  if (settings.maxAspectRatio > 0.0) {
    decimater.add(aspectRatio);
    decimater.module(aspectRatio).set_aspect_ratio(static_cast<float>(settings.maxAspectRatio));
  }
  decimater.add(progMesh);
  decimater.add(wedges);
  std::vector<std::uint32_t> originalIndices;
  for (std::uint32_t t : segment.triangles)
    for (std::size_t k = 0; k < 3; ++k)
      originalIndices.push_back(indices[std::size_t(t) * 3 + k]);
  const TriangleTree original(positions, originalIndices);
  decimater.module(wedges).setup(&corners, &normals, &original, &result.records);
  if (!decimater.initialize())
    return result;
  decimater.decimate(0); // to the end: the whole progressive mesh
  assert(decimater.module(progMesh).pmi().size() == result.records.size());
  return result;
}

} // namespace

ProgressiveMesh ProgressiveMesh::build(const SkinnedMesh& mesh, const MeshSegmentation& segmentation,
                                       const ProgressiveMeshSettings& settings) {
  assert(segmentation.weld.size() == mesh.vertexCount());
  assert(settings.maxNormalDeviationDegrees > 0.0 && settings.maxNormalDeviationDegrees <= 180.0);
  silenceOpenMeshOnce();
  ProgressiveMesh out;
  out.m_indices = mesh.indices;
  out.m_weld = segmentation.weld;
  out.m_locked = segmentation.locked;
  out.m_triangleCount = mesh.triangleCount();
  out.m_segments.resize(segmentation.segments.size());
  std::vector<std::uint8_t> newlyLocked(mesh.vertexCount(), 0); // by welded vertex
  const std::vector<glm::vec3> normals = mesh.normals.empty() ? faceWeightedNormals(mesh, segmentation) : mesh.normals;

  for (std::size_t s = 0; s < segmentation.segments.size(); ++s) {
    SegmentResult result =
        decimateSegment(mesh.indices, segmentation, segmentation.segments[s], mesh.positions, normals, settings);
    Segment& segment = out.m_segments[s];
    segment.triangles = segmentation.segments[s].triangles.size();
    double running = 0.0;
    segment.collapses.reserve(result.records.size());
    for (const Record& record : result.records) {
      running = std::max(running, record.distanceCm);
      Collapse collapse;
      collapse.wedges = record.plan.wedges;
      for (int i = 0; i < record.plan.wedges; ++i) {
        collapse.from[i] = record.plan.from[i];
        collapse.to[i] = record.plan.to[i];
      }
      collapse.removedTriangles = record.removedTriangles;
      collapse.cost = running;
      segment.collapses.push_back(collapse);
    }
    for (std::uint32_t welded : result.newlyLocked)
      newlyLocked[welded] = 1;
  }
  for (std::size_t v = 0; v < out.m_locked.size(); ++v)
    if (newlyLocked[out.m_weld[v]])
      out.m_locked[v] = 1;
  out.m_lockedCount = static_cast<int>(std::count(out.m_locked.begin(), out.m_locked.end(), std::uint8_t(1)));

  for (std::size_t s = 0; s < out.m_segments.size(); ++s)
    for (std::size_t i = 0; i < out.m_segments[s].collapses.size(); ++i)
      out.m_order.push_back(OrderEntry{static_cast<int>(s), static_cast<std::uint32_t>(i)});
  std::sort(out.m_order.begin(), out.m_order.end(), [&](const OrderEntry& a, const OrderEntry& b) {
    const double ca = out.m_segments[static_cast<std::size_t>(a.segment)].collapses[a.index].cost;
    const double cb = out.m_segments[static_cast<std::size_t>(b.segment)].collapses[b.index].cost;
    if (ca != cb)
      return ca < cb;
    if (a.segment != b.segment)
      return a.segment < b.segment;
    return a.index < b.index;
  });
  out.m_trianglesAfter.resize(out.m_order.size() + 1);
  out.m_trianglesAfter[0] = out.m_triangleCount;
  for (std::size_t k = 0; k < out.m_order.size(); ++k) {
    const OrderEntry& entry = out.m_order[k];
    out.m_trianglesAfter[k + 1] =
        out.m_trianglesAfter[k] - out.m_segments[static_cast<std::size_t>(entry.segment)].collapses[entry.index].removedTriangles;
  }
  return out;
}

std::size_t ProgressiveMesh::collapsesFor(std::size_t triangles) const {
  // m_trianglesAfter is non-increasing
  const auto it = std::partition_point(m_trianglesAfter.begin(), m_trianglesAfter.end(),
                                       [&](std::size_t count) { return count > triangles; });
  if (it == m_trianglesAfter.end())
    return collapseCount();
  return static_cast<std::size_t>(it - m_trianglesAfter.begin());
}

double ProgressiveMesh::costAt(std::size_t collapses) const {
  assert(collapses <= collapseCount());
  if (collapses == 0)
    return 0.0;
  const OrderEntry& entry = m_order[collapses - 1];
  return m_segments[static_cast<std::size_t>(entry.segment)].collapses[entry.index].cost;
}

std::size_t ProgressiveMesh::segmentCollapseCount(int segment) const {
  return m_segments[static_cast<std::size_t>(segment)].collapses.size();
}

std::size_t ProgressiveMesh::segmentTriangleCount(int segment) const {
  return m_segments[static_cast<std::size_t>(segment)].triangles;
}

std::size_t ProgressiveMesh::segmentTrianglesAfter(int segment, std::size_t collapses) const {
  const Segment& s = m_segments[static_cast<std::size_t>(segment)];
  assert(collapses <= s.collapses.size());
  std::size_t count = s.triangles;
  for (std::size_t i = 0; i < collapses; ++i)
    count -= s.collapses[i].removedTriangles;
  return count;
}

double ProgressiveMesh::segmentCostAt(int segment, std::size_t collapses) const {
  const Segment& s = m_segments[static_cast<std::size_t>(segment)];
  assert(collapses <= s.collapses.size());
  return collapses == 0 ? 0.0 : s.collapses[collapses - 1].cost;
}

std::vector<std::size_t> ProgressiveMesh::segmentCollapses(std::size_t collapses) const {
  assert(collapses <= collapseCount());
  std::vector<std::size_t> out(m_segments.size(), 0);
  for (std::size_t k = 0; k < collapses; ++k)
    ++out[static_cast<std::size_t>(m_order[k].segment)];
  return out;
}

MeshLevelIndices ProgressiveMesh::level(std::size_t collapses) const {
  return levelPerSegment(segmentCollapses(collapses));
}

MeshLevelIndices ProgressiveMesh::levelPerSegment(std::span<const std::size_t> perSegment) const {
  assert(perSegment.size() == m_segments.size());
  std::vector<std::uint32_t> target(m_weld.size());
  for (std::size_t v = 0; v < target.size(); ++v)
    target[v] = static_cast<std::uint32_t>(v);
  for (std::size_t s = 0; s < m_segments.size(); ++s) {
    const Segment& segment = m_segments[s];
    assert(perSegment[s] <= segment.collapses.size());
    for (std::size_t i = 0; i < perSegment[s]; ++i) {
      const Collapse& collapse = segment.collapses[i];
      for (int w = 0; w < collapse.wedges; ++w)
        target[collapse.from[w]] = collapse.to[w];
    }
  }
  return extract(target);
}

MeshLevelIndices ProgressiveMesh::extract(const std::vector<std::uint32_t>& target) const {
  std::vector<std::uint32_t> root = target;
  const auto find = [&](std::uint32_t v) {
    std::uint32_t r = v;
    while (root[r] != r)
      r = root[r];
    while (root[v] != r) { // path compression
      const std::uint32_t next = root[v];
      root[v] = r;
      v = next;
    }
    return r;
  };
  MeshLevelIndices out;
  out.indices.reserve(m_indices.size());
  out.triangles.reserve(m_triangleCount);
  for (std::size_t t = 0; t < m_triangleCount; ++t) {
    const std::uint32_t a = find(m_indices[t * 3]), b = find(m_indices[t * 3 + 1]), c = find(m_indices[t * 3 + 2]);
    const std::uint32_t wa = m_weld[a], wb = m_weld[b], wc = m_weld[c];
    if (wa == wb || wb == wc || wa == wc) {
      // collapsed away; a triangle that was degenerate from the start stays
      const std::uint32_t oa = m_weld[m_indices[t * 3]], ob = m_weld[m_indices[t * 3 + 1]],
                          oc = m_weld[m_indices[t * 3 + 2]];
      if (!(oa == ob || ob == oc || oa == oc))
        continue;
    }
    out.indices.insert(out.indices.end(), {a, b, c});
    out.triangles.push_back(static_cast<std::uint32_t>(t));
  }
  return out;
}

} // namespace mlod
