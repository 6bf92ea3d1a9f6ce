#include "core/mesh/progressive_mesh.h"

#include "core/cancel.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstring>
#include <limits>
#include <queue>
#include <unordered_map>

namespace mlod {

namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

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
// weighs it: the error then grows linearly with a part's size, which keeps silhouettes
// (BCN_Epileptic at 50%: 0.36% -> 0.31% of the diagonal animated; area weights rank a large
// part's small move above a thin part's large one).
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

// A corner's position bits and, on a skinned mesh, its influences: corners at one position
// that a different skin moves apart are not one surface point.
struct WeldKey {
  std::uint32_t bits[3 + 2 * kMaxInfluences] = {};
  bool operator==(const WeldKey& other) const { return std::memcmp(bits, other.bits, sizeof bits) == 0; }
};

struct WeldHash {
  std::size_t operator()(const WeldKey& k) const {
    std::size_t h = 0;
    for (std::uint32_t b : k.bits)
      h = h * 1000003u ^ b;
    return h;
  }
};

std::uint64_t edgeKey(std::uint32_t a, std::uint32_t b) {
  return (std::uint64_t(a) << 32) | b;
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

struct Candidate {
  std::uint32_t target = kNone; // welded vertex
  double cost = 0.0;
  bool attribute = false; // needs wedges the edge does not map
};

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

// Builds the collapse order: the state of a simplification in progress.
class ProgressiveMeshBuilder {
public:
  ProgressiveMeshBuilder(const SkinnedMesh& mesh, std::span<const std::vector<glm::vec3>> poses,
                         std::span<const float> importance, const ProgressiveMeshSettings& settings,
                         ProgressiveMesh& out)
      : m_mesh(mesh), m_settings(settings), m_out(out), m_poseCount(poses.size()) {
    weld();
    classify();
    accumulateQuadrics(poses, importance);
    findComponents();
  }

  void run(const std::atomic<bool>* cancel);

private:
  std::uint32_t welded(std::uint32_t v) const { return m_out.m_weld[v]; }
  const glm::dvec3& position(std::uint32_t w, std::size_t pose) const {
    return m_positions[std::size_t(w) * m_poseCount + pose];
  }
  Quadric& quadric(std::uint32_t w, std::size_t pose) { return m_quadrics[std::size_t(w) * m_poseCount + pose]; }

  void weld();
  void classify();
  void accumulateQuadrics(std::span<const std::vector<glm::vec3>> poses, std::span<const float> importance);
  // Drops dead triangles from w's fan.
  std::vector<std::uint32_t>& fan(std::uint32_t w);
  Candidate evaluate(std::uint32_t u);
  // The wedge map of u -> v over u's fan; false when the edge's triangles map a wedge two ways.
  bool wedgeMap(std::uint32_t u, std::uint32_t v, const std::vector<std::uint32_t>& fanU, bool& out_attribute);
  bool linkHolds(std::uint32_t u, std::uint32_t v, int edgeTriangles);
  bool flips(std::uint32_t u, std::uint32_t v, const std::vector<std::uint32_t>& fanU) const;
  void collapse(std::uint32_t u, std::uint32_t v, double cost, bool attribute);
  void push(std::uint32_t u);
  // Connected components (over welded vertices) and what pruning each costs.
  void findComponents();
  // Removes component c's live triangles as one step; false when it may not go (the last
  // component with triangles).
  bool prune(std::uint32_t c, double cost);

  const SkinnedMesh& m_mesh;
  const ProgressiveMeshSettings& m_settings;
  ProgressiveMesh& m_out;
  std::size_t m_poseCount;

  std::vector<std::uint32_t> m_corners;           // current wedge per corner
  std::vector<std::uint8_t> m_alive;              // per triangle
  std::vector<std::uint8_t> m_degenerate;         // per triangle: two corners welded together in the input
  std::vector<std::vector<std::uint32_t>> m_fans; // per welded vertex: its triangles (some maybe dead)
  std::vector<std::uint8_t> m_lockedWelded;       // per welded vertex
  std::vector<std::uint8_t> m_removed;            // per welded vertex: collapsed away
  std::vector<std::uint32_t> m_version;           // per welded vertex
  std::vector<glm::dvec3> m_positions;            // [welded * poses + pose]
  std::vector<Quadric> m_quadrics;                // [welded * poses + pose]
  std::vector<double> m_weight; // per welded vertex: its quadrics' triangle weights merged (bind pose, no importance)
  std::priority_queue<HeapEntry> m_heap;
  std::size_t m_triangles = 0;
  // Connected components: per welded vertex its component (kNone where no triangle uses it);
  // per component its welded vertices, live triangles, pruning cost, and whether it may go.
  struct Component {
    std::vector<std::uint32_t> vertices;
    std::size_t triangles = 0;
    double pruneCost = 0.0;
    bool prunable = true;
  };
  std::vector<std::uint32_t> m_component;
  std::vector<Component> m_components;
  std::size_t m_liveComponents = 0;
  bool m_sawAttribute = false;

  // scratch of evaluate()
  std::vector<std::pair<std::uint32_t, int>> m_neighbours;    // welded neighbour, triangles on the edge
  std::vector<std::pair<std::uint32_t, std::uint32_t>> m_map; // wedge of u -> wedge of v
  std::vector<std::uint32_t> m_scratch;
};

void ProgressiveMeshBuilder::weld() {
  const std::size_t n = m_mesh.vertexCount();
  m_out.m_weld.resize(n);
  std::unordered_map<WeldKey, std::uint32_t, WeldHash> first;
  first.reserve(n);
  int count = 0;
  for (std::size_t v = 0; v < n; ++v) {
    WeldKey key;
    std::memcpy(key.bits, &m_mesh.positions[v], 3 * sizeof(std::uint32_t));
    if (m_mesh.skinned()) {
      for (int i = 0; i < kMaxInfluences; ++i)
        key.bits[3 + i] = m_mesh.joints[v][i];
      std::memcpy(key.bits + 3 + kMaxInfluences, &m_mesh.weights[v], kMaxInfluences * sizeof(std::uint32_t));
    }
    const auto [it, inserted] = first.emplace(key, static_cast<std::uint32_t>(v));
    m_out.m_weld[v] = it->second;
    count += inserted ? 1 : 0;
  }
  m_out.m_weldedCount = count;
}

void ProgressiveMeshBuilder::classify() {
  const std::size_t n = m_mesh.vertexCount();
  const std::size_t triangles = m_mesh.triangleCount();
  m_out.m_indices = m_mesh.indices;
  m_out.m_triangleCount = triangles;
  m_corners = m_mesh.indices;
  m_alive.assign(triangles, 1);
  m_degenerate.assign(triangles, 0);
  m_fans.resize(n);
  m_lockedWelded.assign(n, 0);
  m_removed.assign(n, 0);
  m_version.assign(n, 0);
  m_triangles = triangles;

  // welded directed edges: how often each is used, and undirected counts
  std::unordered_map<std::uint64_t, int> directed, undirected;
  directed.reserve(triangles * 3);
  undirected.reserve(triangles * 3);
  for (std::size_t t = 0; t < triangles; ++t) {
    const std::uint32_t w[3] = {welded(m_corners[t * 3]), welded(m_corners[t * 3 + 1]), welded(m_corners[t * 3 + 2])};
    if (w[0] == w[1] || w[1] == w[2] || w[2] == w[0]) {
      m_degenerate[t] = 1; // kept as it is, its vertices locked
      for (std::uint32_t x : w)
        m_lockedWelded[x] = 1;
      continue;
    }
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t a = w[e], b = w[(e + 1) % 3];
      ++directed[edgeKey(a, b)];
      ++undirected[edgeKey(std::min(a, b), std::max(a, b))];
    }
    for (std::uint32_t x : w)
      m_fans[x].push_back(static_cast<std::uint32_t>(t));
  }
  // non-manifold guards: an edge of three or more triangles, or used twice in one
  // direction (a fold or inconsistent orientation); more than two open edges at a vertex
  std::vector<int> openEdges(n, 0);
  for (const auto& [key, count] : undirected) {
    const auto a = static_cast<std::uint32_t>(key >> 32), b = static_cast<std::uint32_t>(key);
    if (count >= 3 || directed[edgeKey(a, b)] >= 2 || directed[edgeKey(b, a)] >= 2)
      m_lockedWelded[a] = m_lockedWelded[b] = 1;
    if (count == 1)
      ++openEdges[a], ++openEdges[b];
  }
  for (std::size_t v = 0; v < n; ++v)
    if (openEdges[v] > 2)
      m_lockedWelded[v] = 1;

  m_out.m_locked.assign(n, 0);
  m_out.m_lockedCount = 0;
  for (std::size_t v = 0; v < n; ++v) {
    m_out.m_locked[v] = m_lockedWelded[welded(static_cast<std::uint32_t>(v))];
    if (welded(static_cast<std::uint32_t>(v)) == v && m_lockedWelded[v])
      ++m_out.m_lockedCount;
  }
}

void ProgressiveMeshBuilder::accumulateQuadrics(std::span<const std::vector<glm::vec3>> poses,
                                                std::span<const float> importance) {
  const std::size_t n = m_mesh.vertexCount();
  m_positions.resize(n * m_poseCount);
  for (std::size_t v = 0; v < n; ++v)
    if (welded(static_cast<std::uint32_t>(v)) == v)
      for (std::size_t p = 0; p < m_poseCount; ++p)
        m_positions[v * m_poseCount + p] = glm::dvec3(poses[p][v]);
  std::vector<double> scale(n, 0.0); // per welded vertex: the largest importance of its wedges
  for (std::size_t v = 0; v < n; ++v) {
    double& s = scale[welded(static_cast<std::uint32_t>(v))];
    s = std::max(s, importance.empty() ? 1.0 : double(importance[v]));
  }
  m_quadrics.assign(n * m_poseCount, Quadric{});
  m_weight.assign(n, 0.0);

  // wedge-level directed edges: a welded edge whose two triangles do not meet in the same
  // wedges on both ends is an attribute seam
  std::unordered_map<std::uint64_t, std::uint8_t> wedgeEdges;
  std::unordered_map<std::uint64_t, int> weldedEdges;
  for (std::size_t t = 0; t < m_mesh.triangleCount(); ++t) {
    if (m_degenerate[t])
      continue;
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t a = m_corners[t * 3 + e], b = m_corners[t * 3 + (e + 1) % 3];
      wedgeEdges[edgeKey(a, b)] = 1;
      const std::uint32_t wa = welded(a), wb = welded(b);
      ++weldedEdges[edgeKey(std::min(wa, wb), std::max(wa, wb))];
    }
  }
  for (std::size_t t = 0; t < m_mesh.triangleCount(); ++t) {
    if (m_degenerate[t])
      continue;
    const std::uint32_t c[3] = {m_corners[t * 3], m_corners[t * 3 + 1], m_corners[t * 3 + 2]};
    const std::uint32_t w[3] = {welded(c[0]), welded(c[1]), welded(c[2])};
    for (std::size_t p = 0; p < m_poseCount; ++p)
      for (std::uint32_t x : w)
        quadricAdd(quadric(x, p),
                   quadricFromTriangle(position(w[0], p), position(w[1], p), position(w[2], p), scale[x]));
    const double area =
        0.5 * glm::length(glm::cross(position(w[1], 0) - position(w[0], 0), position(w[2], 0) - position(w[0], 0)));
    for (std::uint32_t x : w)
      m_weight[x] += std::sqrt(area);
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t a = c[e], b = c[(e + 1) % 3];
      const std::uint32_t wa = w[e], wb = w[(e + 1) % 3], wc = w[(e + 2) % 3];
      const int count = weldedEdges[edgeKey(std::min(wa, wb), std::max(wa, wb))];
      double weight = 0.0;
      if (count == 1)
        weight = m_settings.borderWeight;
      else if (count == 2 && !wedgeEdges.count(edgeKey(b, a)))
        weight = m_settings.seamWeight;
      if (!(weight > 0.0))
        continue;
      for (std::size_t p = 0; p < m_poseCount; ++p) {
        quadricAdd(quadric(wa, p),
                   quadricFromEdge(position(wa, p), position(wb, p), position(wc, p), weight * scale[wa]));
        quadricAdd(quadric(wb, p),
                   quadricFromEdge(position(wa, p), position(wb, p), position(wc, p), weight * scale[wb]));
      }
    }
  }
}

void ProgressiveMeshBuilder::findComponents() {
  const std::size_t n = m_mesh.vertexCount();
  std::vector<std::uint32_t> parent(n);
  for (std::size_t v = 0; v < n; ++v)
    parent[v] = static_cast<std::uint32_t>(v);
  const auto find = [&](std::uint32_t x) {
    while (parent[x] != x)
      x = parent[x] = parent[parent[x]];
    return x;
  };
  for (std::size_t t = 0; t < m_mesh.triangleCount(); ++t)
    for (int k = 1; k < 3; ++k) {
      const std::uint32_t a = find(welded(m_corners[t * 3])), b = find(welded(m_corners[t * 3 + std::size_t(k)]));
      if (a != b)
        parent[std::max(a, b)] = std::min(a, b);
    }
  m_component.assign(n, kNone);
  std::vector<std::uint32_t> index(n, kNone); // per root: its component
  for (std::size_t t = 0; t < m_mesh.triangleCount(); ++t) {
    const std::uint32_t root = find(welded(m_corners[t * 3]));
    if (index[root] == kNone) {
      index[root] = static_cast<std::uint32_t>(m_components.size());
      m_components.emplace_back();
    }
    Component& component = m_components[index[root]];
    ++component.triangles;
    component.prunable &= !m_degenerate[t];
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t w = welded(m_corners[t * 3 + std::size_t(k)]);
      if (m_component[w] == kNone) {
        m_component[w] = index[root];
        component.vertices.push_back(w);
        component.prunable &= !m_lockedWelded[w];
      }
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
      for (std::uint32_t w : component.vertices) {
        centre += position(w, p);
        weight += quadric(w, p).w;
      }
      centre /= double(component.vertices.size());
      double radius2 = 0.0;
      for (std::uint32_t w : component.vertices) {
        const glm::dvec3 d = position(w, p) - centre;
        radius2 = std::max(radius2, glm::dot(d, d));
      }
      component.pruneCost += weight * radius2;
    }
    double total = 0.0; // collapse costs are per unit of weight (evaluate()): so is this one
    for (std::uint32_t w : component.vertices)
      total += m_weight[w];
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
  for (std::uint32_t w : component.vertices) {
    if (m_removed[w])
      continue;
    for (std::uint32_t t : fan(w)) {
      m_alive[t] = 0;
      --m_triangles;
      m_out.m_pruned.push_back(t);
    }
    m_fans[w].clear();
    m_removed[w] = 1;
    ++m_version[w];
  }
  record.prunedCount = static_cast<std::uint32_t>(m_out.m_pruned.size() - record.firstPruned);
  component.triangles = 0;
  --m_liveComponents;
  m_out.m_collapses.push_back(record);
  m_out.m_trianglesAfter.push_back(m_triangles);
  return true;
}

std::vector<std::uint32_t>& ProgressiveMeshBuilder::fan(std::uint32_t w) {
  std::vector<std::uint32_t>& f = m_fans[w];
  f.erase(std::remove_if(f.begin(), f.end(), [&](std::uint32_t t) { return !m_alive[t]; }), f.end());
  return f;
}

bool ProgressiveMeshBuilder::wedgeMap(std::uint32_t u, std::uint32_t v, const std::vector<std::uint32_t>& fanU,
                                      bool& out_attribute) {
  m_map.clear();
  out_attribute = false;
  // the edge's triangles map u's corner in them onto v's corner in them
  for (std::uint32_t t : fanU) {
    std::uint32_t cu = kNone, cv = kNone;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t c = m_corners[std::size_t(t) * 3 + k];
      if (welded(c) == u)
        cu = c;
      else if (welded(c) == v)
        cv = c;
    }
    if (cv == kNone)
      continue;
    const auto found = std::find_if(m_map.begin(), m_map.end(), [&](const auto& e) { return e.first == cu; });
    if (found == m_map.end())
      m_map.emplace_back(cu, cv);
    else if (found->second != cv)
      return false; // a corner that would have to go two ways: a half-seam
  }
  // wedges of u on no triangle of the edge: an attribute collapse, onto v's wedge with the
  // nearest normal, then UV
  for (std::uint32_t t : fanU)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t c = m_corners[std::size_t(t) * 3 + k];
      if (welded(c) != u || std::any_of(m_map.begin(), m_map.end(), [&](const auto& e) { return e.first == c; }))
        continue;
      out_attribute = true;
      m_scratch.clear();
      for (std::uint32_t s : fan(v))
        for (int j = 0; j < 3; ++j) {
          const std::uint32_t d = m_corners[std::size_t(s) * 3 + j];
          if (welded(d) == v && std::find(m_scratch.begin(), m_scratch.end(), d) == m_scratch.end())
            m_scratch.push_back(d);
        }
      std::uint32_t best = kNone;
      double bestScore = std::numeric_limits<double>::max();
      for (std::uint32_t d : m_scratch) {
        double score = 0.0;
        if (!m_mesh.normals.empty())
          score += 4.0 * (1.0 - double(glm::dot(m_mesh.normals[c], m_mesh.normals[d])));
        if (!m_mesh.uvs.empty()) {
          const glm::dvec2 delta = glm::dvec2(m_mesh.uvs[c]) - glm::dvec2(m_mesh.uvs[d]);
          score += glm::dot(delta, delta);
        }
        // (a NaN score, from a degenerate triangle's normal, must still name a wedge)
        if (best == kNone || score < bestScore)
          bestScore = score, best = d;
      }
      if (best == kNone)
        return false; // v keeps no wedge of its own to take u's: no collapse
      m_map.emplace_back(c, best);
    }
  return true;
}

bool ProgressiveMeshBuilder::linkHolds(std::uint32_t u, std::uint32_t v, int edgeTriangles) {
  // u's neighbours are in m_neighbours; count v's neighbours among them
  int common = 0;
  m_scratch.clear();
  for (std::uint32_t t : fan(v))
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t w = welded(m_corners[std::size_t(t) * 3 + k]);
      if (w == v || w == u || std::find(m_scratch.begin(), m_scratch.end(), w) != m_scratch.end())
        continue;
      m_scratch.push_back(w);
      if (std::any_of(m_neighbours.begin(), m_neighbours.end(), [&](const auto& e) { return e.first == w; }))
        ++common;
    }
  return common == edgeTriangles;
}

bool ProgressiveMeshBuilder::flips(std::uint32_t u, std::uint32_t v, const std::vector<std::uint32_t>& fanU) const {
  // needs m_map, the wedge map of u -> v (wedgeMap())
  const bool shaded = !m_mesh.normals.empty();
  for (std::uint32_t t : fanU) {
    std::uint32_t w[3], c[3];
    int at = -1;
    bool hasV = false;
    for (int k = 0; k < 3; ++k) {
      c[k] = m_corners[std::size_t(t) * 3 + std::size_t(k)];
      w[k] = welded(c[k]);
      hasV |= w[k] == v;
      if (w[k] == u)
        at = k;
    }
    if (hasV || at < 0)
      continue; // the edge's own triangles go away
    const std::uint32_t a = w[(at + 1) % 3], b = w[(at + 2) % 3];
    for (std::size_t p = 0; p < m_poseCount; ++p) {
      const glm::dvec3& pa = position(a, p);
      const glm::dvec3& pb = position(b, p);
      const glm::dvec3 before = glm::cross(pa - position(u, p), pb - position(u, p));
      const glm::dvec3 after = glm::cross(pa - position(v, p), pb - position(v, p));
      // note: a triangle already degenerate in a pose says nothing about a flip there
      if (glm::length(before) * glm::length(after) > 0.0 && glm::dot(before, after) <= 0.0)
        return true;
      if (p != 0)
        continue;
      if (!(glm::dot(after, after) > 0.0) && glm::dot(before, before) > 0.0)
        return true; // would become degenerate in the bind pose
      if (!shaded)
        continue;
      // nor turn its back on its corners' normals (it would shade inside out), unless the
      // input triangle already did
      const std::uint32_t moved =
          std::find_if(m_map.begin(), m_map.end(), [&](const auto& e) { return e.first == c[at]; })->second;
      const glm::dvec3 shadingBefore = glm::dvec3(m_mesh.normals[c[0]] + m_mesh.normals[c[1]] + m_mesh.normals[c[2]]);
      const glm::dvec3 shadingAfter =
          shadingBefore - glm::dvec3(m_mesh.normals[c[at]]) + glm::dvec3(m_mesh.normals[moved]);
      if (glm::dot(after, shadingAfter) < 0.0 && glm::dot(before, shadingBefore) >= 0.0)
        return true;
    }
  }
  return false;
}

Candidate ProgressiveMeshBuilder::evaluate(std::uint32_t u) {
  Candidate best;
  if (m_lockedWelded[u] || m_removed[u])
    return best;
  const std::vector<std::uint32_t>& fanU = fan(u);
  if (fanU.empty())
    return best;
  m_neighbours.clear();
  for (std::uint32_t t : fanU)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t w = welded(m_corners[std::size_t(t) * 3 + k]);
      if (w == u)
        continue;
      auto found = std::find_if(m_neighbours.begin(), m_neighbours.end(), [&](const auto& e) { return e.first == w; });
      if (found == m_neighbours.end())
        m_neighbours.emplace_back(w, 1);
      else
        ++found->second;
    }
  bool border = false;
  for (const auto& [w, count] : m_neighbours) {
    if (count > 2)
      return best; // not manifold here (a guard; the link condition keeps it from arising)
    border |= count == 1;
  }

  struct Option {
    double cost;
    std::uint32_t v;
    int edgeTriangles;
  };
  std::vector<Option> options;
  const glm::dvec3& bindU = position(u, 0);
  for (const auto& [v, count] : m_neighbours) {
    if (border && count != 1)
      continue; // a border vertex moves only along its border
    double cost = 0.0;
    for (std::size_t p = 0; p < m_poseCount; ++p)
      cost += quadricError(quadric(u, p), position(v, p));
    // note: a collapse whose quadric cost is nil (u on every plane of its fan at v, as on a
    // ridge where mirrored halves meet) still moves the surface by |u - v|; a small weight
    // on that distance ranks short moves first (WusonSMD at 25%: 2.74% -> 2.10% of the
    // diagonal in the bind pose)
    if (m_settings.moveWeight > 0.0) {
      const glm::dvec3 edge = position(v, 0) - bindU;
      cost += m_settings.moveWeight * quadric(u, 0).w * glm::dot(edge, edge);
    }
    if (m_mesh.skinned() && m_settings.skinWeight > 0.0) {
      const double d = skinDistance(m_mesh.joints[u], m_mesh.weights[u], m_mesh.joints[v], m_mesh.weights[v]);
      const glm::dvec3 edge = position(v, 0) - bindU;
      cost += m_settings.skinWeight * d * quadric(u, 0).w * glm::dot(edge, edge);
    }
    // note: per unit of the weight u's quadrics gathered (a weighted mean squared distance,
    // as meshoptimizer ranks): the sum alone ranks a small part that moves far (an eye, a
    // finger tip) below a large one that moves a little, and the symmetric max distance the
    // levels are measured by is set by the former (WusonSMD at 25%: 2.10% -> 1.46% of the
    // diagonal; BCN_Epileptic animated 1.02% -> 0.79%); importance still scales the
    // quadrics (not the weight they are divided by), so it still ranks a joint's vertices later
    if (m_weight[u] > 0.0)
      cost /= m_weight[u];
    options.push_back({cost, v, count});
  }
  std::sort(options.begin(), options.end(), [](const Option& a, const Option& b) { return a.cost < b.cost; });
  // the cheapest allowed collapse: a seam is a cost (its edge quadrics), not a second tier
  // after every clean collapse (that left cheap seam collapses behind costly clean ones:
  // Testwuson at 10%, 9.77% -> 5.90% of the diagonal)
  for (const Option& option : options) {
    bool attribute = false;
    if (!wedgeMap(u, option.v, fanU, attribute))
      continue;
    if (!linkHolds(u, option.v, option.edgeTriangles) || flips(u, option.v, fanU))
      continue;
    return Candidate{option.v, option.cost, attribute};
  }
  return best;
}

void ProgressiveMeshBuilder::push(std::uint32_t u) {
  ++m_version[u];
  const Candidate c = evaluate(u);
  if (c.target != kNone)
    m_heap.push(HeapEntry{c.cost, u, c.target, m_version[u], c.attribute});
}

void ProgressiveMeshBuilder::collapse(std::uint32_t u, std::uint32_t v, double cost, bool attribute) {
  std::vector<std::uint32_t> fanU = fan(u);
  bool mapAttribute = false;
  // ranked legal; a map that cannot be made now (damaged input: ../shared/repro/crash_segv_min.obj
  // mapped a corner to no wedge and crashed) leaves the mesh as it is
  if (!wedgeMap(u, v, fanU, mapAttribute))
    return;
  assert(mapAttribute == attribute);
  (void)attribute;
  ProgressiveMesh::Collapse record;
  record.firstWedge = static_cast<std::uint32_t>(m_out.m_from.size());
  record.wedgeCount = static_cast<std::uint32_t>(m_map.size());
  record.cost = cost;
  for (const auto& [from, to] : m_map) {
    m_out.m_from.push_back(from);
    m_out.m_to.push_back(to);
  }
  std::vector<std::uint32_t>& fanV = m_fans[v];
  for (std::uint32_t t : fanU) {
    bool hasV = false;
    for (int k = 0; k < 3; ++k)
      hasV |= welded(m_corners[std::size_t(t) * 3 + k]) == v;
    if (hasV) {
      m_alive[t] = 0;
      --m_triangles;
      Component& component = m_components[m_component[u]];
      if (--component.triangles == 0)
        --m_liveComponents;
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      std::uint32_t& c = m_corners[std::size_t(t) * 3 + k];
      if (welded(c) == u) {
        const auto mapped = std::find_if(m_map.begin(), m_map.end(), [&](const auto& e) { return e.first == c; });
        assert(mapped != m_map.end()); // wedgeMap() maps every corner of u in its fan
        c = mapped->second;
      }
    }
    fanV.push_back(t);
  }
  m_fans[u].clear();
  m_removed[u] = 1;
  for (std::size_t p = 0; p < m_poseCount; ++p)
    quadricAdd(quadric(v, p), quadric(u, p));
  m_weight[v] += m_weight[u];
  m_out.m_collapses.push_back(record);
  m_out.m_trianglesAfter.push_back(m_triangles);

  // v and its neighbours see a new fan: rank them again
  m_scratch.clear();
  for (std::uint32_t t : fan(v))
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t w = welded(m_corners[std::size_t(t) * 3 + k]);
      if (std::find(m_scratch.begin(), m_scratch.end(), w) == m_scratch.end())
        m_scratch.push_back(w);
    }
  const std::vector<std::uint32_t> around = m_scratch;
  for (std::uint32_t w : around)
    push(w);
}

void ProgressiveMeshBuilder::run(const std::atomic<bool>* cancel) {
  m_out.m_trianglesAfter.assign(1, m_triangles);
  m_out.m_cleanCollapses = 0;
  for (std::uint32_t v = 0; v < m_mesh.vertexCount(); ++v)
    if (welded(v) == v)
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
    if (top.version != m_version[top.vertex] || m_removed[top.vertex])
      continue;
    if (top.attribute && !m_sawAttribute) {
      m_out.m_cleanCollapses = m_out.m_collapses.size();
      m_sawAttribute = true;
    }
    collapse(top.vertex, top.target, top.cost, top.attribute);
  }
  if (!m_sawAttribute)
    m_out.m_cleanCollapses = m_out.m_collapses.size();
}

ProgressiveMesh ProgressiveMesh::build(const SkinnedMesh& mesh, std::span<const std::vector<glm::vec3>> poses,
                                       std::span<const float> vertexImportance,
                                       const ProgressiveMeshSettings& settings, const std::atomic<bool>* cancel) {
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
    const bool degenerateBefore = m_weld[m_indices[t * 3]] == m_weld[m_indices[t * 3 + 1]] ||
                                  m_weld[m_indices[t * 3 + 1]] == m_weld[m_indices[t * 3 + 2]] ||
                                  m_weld[m_indices[t * 3 + 2]] == m_weld[m_indices[t * 3]];
    if (!degenerateBefore && (wa == wb || wb == wc || wc == wa))
      continue;
    out.indices.insert(out.indices.end(), {a, b, c});
    out.triangles.push_back(static_cast<std::uint32_t>(t));
  }
  assert(out.triangles.size() == m_trianglesAfter[collapses]);
  return out;
}

} // namespace mlod
