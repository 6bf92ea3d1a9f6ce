#include "core/mesh/surface_distance.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <limits>
#include <numeric>
#include <unordered_set>

namespace mlod {

namespace {

struct Box {
  glm::dvec3 lo{std::numeric_limits<double>::max()};
  glm::dvec3 hi{std::numeric_limits<double>::lowest()};
  void add(const glm::dvec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  void add(const Box& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
  double distanceSquared(const glm::dvec3& p) const {
    const glm::dvec3 d = glm::max(glm::max(lo - p, p - hi), glm::dvec3(0.0));
    return glm::dot(d, d);
  }
};

struct Triangle {
  glm::dvec3 a, b, c;
};

// The point of triangle abc nearest to p, by Voronoi regions (Ericson, "Real-Time Collision
// Detection", 5.1.5).
glm::dvec3 closestPoint(const glm::dvec3& p, const Triangle& t) {
  const glm::dvec3 ab = t.b - t.a, ac = t.c - t.a, ap = p - t.a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0)
    return t.a;
  const glm::dvec3 bp = p - t.b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3)
    return t.b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0)
    return t.a + ab * (d1 / (d1 - d3));
  const glm::dvec3 cp = p - t.c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6)
    return t.c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0)
    return t.a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
    return t.b + (t.c - t.b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double sum = va + vb + vc;
  if (!(sum > 0.0)) { // degenerate triangle: the nearest corner will do
    const double da = glm::dot(p - t.a, p - t.a), db = glm::dot(p - t.b, p - t.b), dc = glm::dot(p - t.c, p - t.c);
    return da <= db && da <= dc ? t.a : (db <= dc ? t.b : t.c);
  }
  return t.a + ab * (vb / sum) + ac * (vc / sum);
}

double triangleDistanceSquared(const glm::dvec3& p, const Triangle& t) {
  const glm::dvec3 d = p - closestPoint(p, t);
  return glm::dot(d, d);
}

using TriangleKey = std::array<std::uint32_t, 3>;

// The same triangle whichever corner comes first (orientation kept).
TriangleKey canonical(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  if (a <= b && a <= c)
    return {a, b, c};
  if (b <= a && b <= c)
    return {b, c, a};
  return {c, a, b};
}

struct KeyHash {
  std::size_t operator()(const TriangleKey& k) const {
    return (std::size_t(k[0]) * 73856093u) ^ (std::size_t(k[1]) * 19349663u) ^ (std::size_t(k[2]) * 83492791u);
  }
};

} // namespace

struct TriangleTree::Impl {
  static constexpr int kLeafSize = 4;
  struct Node {
    Box box;
    int first = 0; // leaf: first triangle; inner: left child (right child = first + 1)
    int count = 0; // triangles in a leaf, 0 for an inner node
  };
  std::vector<Triangle> triangles;
  std::vector<Node> nodes;

  // Fills node `slot` with triangles order[first, first + count): a leaf, or an inner node
  // whose two children are stored next to each other.
  void fill(int slot, std::vector<int>& order, const std::vector<glm::dvec3>& centroids, const std::vector<Box>& boxes,
            int first, int count) {
    Box box, centroidBox;
    for (int i = first; i < first + count; ++i) {
      const auto t = static_cast<std::size_t>(order[static_cast<std::size_t>(i)]);
      box.add(boxes[t]);
      centroidBox.add(centroids[t]);
    }
    nodes[static_cast<std::size_t>(slot)].box = box;
    if (count <= kLeafSize) {
      nodes[static_cast<std::size_t>(slot)].first = first;
      nodes[static_cast<std::size_t>(slot)].count = count;
      return;
    }
    const glm::dvec3 extent = centroidBox.hi - centroidBox.lo;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const int half = count / 2;
    std::nth_element(order.begin() + first, order.begin() + first + half, order.begin() + first + count,
                     [&](int a, int b) {
                       return centroids[static_cast<std::size_t>(a)][axis] < centroids[static_cast<std::size_t>(b)][axis];
                     });
    const int left = static_cast<int>(nodes.size());
    nodes.emplace_back();
    nodes.emplace_back();
    nodes[static_cast<std::size_t>(slot)].first = left;
    nodes[static_cast<std::size_t>(slot)].count = 0;
    fill(left, order, centroids, boxes, first, half);
    fill(left + 1, order, centroids, boxes, first + half, count - half);
  }

  // The smallest squared distance found, stopping as soon as one is <= stopBelow; its
  // triangle goes to *out_triangle.
  double search(const glm::dvec3& point, double limit, double stopBelow, int* out_triangle) const {
    double best = limit;
    if (nodes.empty())
      return best;
    int stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes[static_cast<std::size_t>(stack[--top])];
      if (node.box.distanceSquared(point) >= best)
        continue;
      if (node.count > 0) {
        for (int i = node.first; i < node.first + node.count; ++i) {
          const double d = triangleDistanceSquared(point, triangles[static_cast<std::size_t>(i)]);
          if (d < best) {
            best = d;
            *out_triangle = i;
          }
        }
        if (best <= stopBelow)
          return best;
        continue;
      }
      const int left = node.first, right = node.first + 1;
      const double dl = nodes[static_cast<std::size_t>(left)].box.distanceSquared(point);
      const double dr = nodes[static_cast<std::size_t>(right)].box.distanceSquared(point);
      assert(top + 2 <= 128); // depth is about log2(triangles / 4)
      if (dl < dr) { // the nearer child first
        stack[top++] = right;
        stack[top++] = left;
      } else {
        stack[top++] = left;
        stack[top++] = right;
      }
    }
    return best;
  }
};

TriangleTree::TriangleTree(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices)
    : m_impl(std::make_unique<Impl>()) {
  assert(indices.size() % 3 == 0);
  const std::size_t count = indices.size() / 3;
  std::vector<Triangle> triangles(count);
  std::vector<glm::dvec3> centroids(count);
  std::vector<Box> boxes(count);
  for (std::size_t t = 0; t < count; ++t) {
    Triangle& tri = triangles[t];
    tri.a = glm::dvec3(positions[indices[t * 3]]);
    tri.b = glm::dvec3(positions[indices[t * 3 + 1]]);
    tri.c = glm::dvec3(positions[indices[t * 3 + 2]]);
    centroids[t] = (tri.a + tri.b + tri.c) / 3.0;
    boxes[t].add(tri.a);
    boxes[t].add(tri.b);
    boxes[t].add(tri.c);
  }
  if (count == 0)
    return;
  std::vector<int> order(count);
  std::iota(order.begin(), order.end(), 0);
  m_impl->nodes.reserve(count);
  m_impl->nodes.emplace_back();
  m_impl->fill(0, order, centroids, boxes, 0, static_cast<int>(count));
  m_impl->triangles.resize(count);
  for (std::size_t i = 0; i < count; ++i)
    m_impl->triangles[i] = triangles[static_cast<std::size_t>(order[i])];
}

TriangleTree::~TriangleTree() = default;
TriangleTree::TriangleTree(TriangleTree&&) noexcept = default;
TriangleTree& TriangleTree::operator=(TriangleTree&&) noexcept = default;

bool TriangleTree::empty() const { return m_impl->triangles.empty(); }

double TriangleTree::nearestSquared(const glm::dvec3& point, double limit, int* out_triangle) const {
  int triangle = -1;
  const double best = m_impl->search(point, limit, -1.0, &triangle);
  if (out_triangle)
    *out_triangle = triangle;
  return best;
}

glm::dvec3 TriangleTree::closestPoint(const glm::dvec3& point, int triangle) const {
  assert(triangle >= 0 && std::size_t(triangle) < m_impl->triangles.size());
  return mlod::closestPoint(point, m_impl->triangles[static_cast<std::size_t>(triangle)]);
}

bool TriangleTree::anyWithin(const glm::dvec3& point, double radiusSquared, int* inout_hint) const {
  if (inout_hint && *inout_hint >= 0 &&
      triangleDistanceSquared(point, m_impl->triangles[static_cast<std::size_t>(*inout_hint)]) <= radiusSquared)
    return true;
  int triangle = -1;
  const bool found =
      m_impl->search(point, std::numeric_limits<double>::infinity(), radiusSquared, &triangle) <= radiusSquared;
  if (found && inout_hint)
    *inout_hint = triangle;
  return found;
}

double pointTriangleDistanceSquared(const glm::dvec3& point, const glm::dvec3& a, const glm::dvec3& b,
                                    const glm::dvec3& c) {
  return triangleDistanceSquared(point, Triangle{a, b, c});
}

int samplingSubdivisions(double longestEdgeCm, double spacingCm) {
  assert(spacingCm > 0.0);
  const double cells = std::ceil(longestEdgeCm / (3.0 * spacingCm));
  const int thirds = std::isfinite(cells) ? static_cast<int>(std::clamp(cells, 1.0, double(kMaxSamplingSubdivisions / 3))) : 1;
  return 3 * thirds;
}

namespace {

double maxDistanceToTree(std::span<const glm::vec3> positions, std::span<const std::uint32_t> from,
                         const std::unordered_set<TriangleKey, KeyHash>& skip, const TriangleTree& tree,
                         double spacingCm, double floorCm) {
  double worst = floorCm * floorCm; // squared
  int hint = -1;       // the triangle that answered the last sample: neighbouring samples ask it first
  for (std::size_t t = 0; t + 2 < from.size(); t += 3) {
    if (skip.count(canonical(from[t], from[t + 1], from[t + 2])))
      continue;
    if (tree.empty())
      return std::numeric_limits<double>::infinity();
    const glm::dvec3 a(positions[from[t]]), b(positions[from[t + 1]]), c(positions[from[t + 2]]);
    const double longest = std::sqrt(std::max({glm::dot(b - a, b - a), glm::dot(c - b, c - b), glm::dot(a - c, a - c)}));
    const int n = samplingSubdivisions(longest, spacingCm);
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const double u = double(i) / n, v = double(j) / n;
        const glm::dvec3 p = a + (b - a) * u + (c - a) * v;
        // note: a sample within the worst distance so far cannot change the result, and
        // finding any triangle that near is much cheaper than finding the nearest
        if (worst > 0.0 && tree.anyWithin(p, worst, &hint))
          continue;
        worst = std::max(worst, tree.nearestSquared(p, std::numeric_limits<double>::infinity(), &hint));
      }
  }
  return std::sqrt(worst);
}

std::unordered_set<TriangleKey, KeyHash> keysOf(std::span<const std::uint32_t> indices) {
  std::unordered_set<TriangleKey, KeyHash> keys;
  keys.reserve(indices.size() / 3);
  for (std::size_t t = 0; t + 2 < indices.size(); t += 3)
    keys.insert(canonical(indices[t], indices[t + 1], indices[t + 2]));
  return keys;
}

} // namespace

double oneSidedMaxDistance(std::span<const glm::vec3> positions, std::span<const std::uint32_t> from,
                           std::span<const std::uint32_t> to, double spacingCm, double floorCm) {
  const TriangleTree tree(positions, to);
  return maxDistanceToTree(positions, from, keysOf(to), tree, spacingCm, floorCm);
}

double oneSidedMaxDistance(std::span<const glm::vec3> positions, std::span<const std::uint32_t> from,
                           std::span<const std::uint32_t> to, const TriangleTree& toTree, double spacingCm,
                           double floorCm) {
  return maxDistanceToTree(positions, from, keysOf(to), toTree, spacingCm, floorCm);
}

double symmetricMaxDistance(std::span<const glm::vec3> positions, std::span<const std::uint32_t> a,
                            std::span<const std::uint32_t> b, double spacingCm, double floorCm) {
  const double ab = oneSidedMaxDistance(positions, a, b, spacingCm, floorCm);
  return oneSidedMaxDistance(positions, b, a, spacingCm, ab);
}

} // namespace mlod
