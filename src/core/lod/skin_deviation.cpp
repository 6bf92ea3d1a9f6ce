#include "core/lod/skin_deviation.h"

#include "core/cancel.h"
#include "core/jpc/parallel_for.h"
#include "core/mesh/skinning.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numeric>

namespace mlod {

namespace {

constexpr std::size_t kGroupVertices = 16;
// Of the largest skinned coordinate: what float rounding may add to a computed distance
// (two renders of a few products and sums each, a difference and a length: ~10 float ulps,
// 6e-7), with room.
constexpr double kRoundingMargin = 1e-5;

// Splits points[begin, end) at the median of the longest side until a group holds at most
// kGroupVertices points.
void group(std::vector<glm::dvec3>& points, std::size_t begin, std::size_t end,
           std::vector<SkinDeviation::Group>& out) {
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
  for (std::size_t i = begin; i < end; ++i) {
    lo = glm::min(lo, points[i]);
    hi = glm::max(hi, points[i]);
  }
  if (end - begin <= kGroupVertices) {
    SkinDeviation::Group g;
    g.centre = 0.5 * (lo + hi);
    for (std::size_t i = begin; i < end; ++i)
      g.radius = std::max(g.radius, glm::length(points[i] - g.centre));
    out.push_back(g);
    return;
  }
  const glm::dvec3 size = hi - lo;
  const int axis = size.x >= size.y && size.x >= size.z ? 0 : size.y >= size.z ? 1 : 2;
  const std::size_t middle = begin + (end - begin) / 2;
  std::nth_element(points.begin() + std::ptrdiff_t(begin), points.begin() + std::ptrdiff_t(middle),
                   points.begin() + std::ptrdiff_t(end),
                   [axis](const glm::dvec3& a, const glm::dvec3& b) { return a[axis] < b[axis]; });
  group(points, begin, middle, out);
  group(points, middle, end, out);
}

// The Frobenius norm of the linear (3 x 3) part: at least how far it stretches any vector.
double linearNorm(const glm::dmat4& m) {
  double sum = 0.0;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r)
      sum += m[c][r] * m[c][r];
  return std::sqrt(sum);
}

} // namespace

SkinDeviation::SkinDeviation(const SkinnedMesh& mesh) {
  if (!mesh.skinned())
    return;
  std::vector<std::vector<glm::dvec3>> points;
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    const glm::dvec3 p(mesh.positions[v]);
    m_extent = std::max(m_extent, glm::length(p));
    for (int i = 0; i < kMaxInfluences && mesh.weights[v][i] != 0.0f; ++i) {
      const std::size_t j = mesh.joints[v][i];
      if (j >= points.size())
        points.resize(j + 1);
      points[j].push_back(p);
    }
  }
  m_groups.resize(points.size());
  for (std::size_t j = 0; j < points.size(); ++j)
    if (!points[j].empty())
      group(points[j], 0, points[j].size(), m_groups[j]);
}

Result<std::vector<double>> SkinDeviation::reachPerFrame(const Skeleton& skeleton, const SkinnedMesh& mesh,
                                                         const Clip& clip, const BoneReduction& bones,
                                                         const SkinnedMesh& levelMesh, const Clip& levelClip,
                                                         const std::atomic<bool>* cancel) const {
  assert(mesh.skinned() && levelMesh.vertexCount() == mesh.vertexCount());
  assert(levelClip.frameCount == clip.frameCount);
  const std::vector<glm::mat4> bake = bakeMatrices(bones, skeleton);

  // A vertex that blends joints rebound to different active joints k differs from
  // sum_i w_i P'_a_i B_i p (what the bound above covers) by sum_k W_k A'_k (q - m_k), where
  // q is its baked position, m_k the weighted mean of B_i p over the influences i rebound to
  // k and A' the linear parts; as sum_k W_k (q - m_k) is q's drift from sum_i w_i B_i p, that
  // is sum_k W_k (A'_k - A'_k0) (q - m_k) plus A'_k0 times the drift, k0 any of its joints:
  // at most max_k |A'_k - A'_k0|_F times sum_k W_k |q - m_k|. Per pair (k0, k), the largest
  // such sum. Every baked vertex: the drift (float rounding in rebindMesh()).
  std::map<std::pair<int, int>, double> pairOffsets; // (k0, k) in bones.skeleton -> cm
  double drift = 0.0, levelExtent = 0.0;
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    levelExtent = std::max(levelExtent, glm::length(glm::dvec3(levelMesh.positions[v])));
    bool baked = false;
    int targets[kMaxInfluences];
    double weights[kMaxInfluences];
    glm::dvec3 means[kMaxInfluences];
    int count = 0;
    glm::dvec3 sum(0.0);
    for (int i = 0; i < kMaxInfluences && mesh.weights[v][i] != 0.0f; ++i) {
      const std::size_t j = mesh.joints[v][i];
      baked = baked || bones.removed[j] != 0;
      const double w = mesh.weights[v][i];
      const glm::dvec3 x = glm::dvec3(glm::dmat4(bake[j]) * glm::dvec4(glm::dvec3(mesh.positions[v]), 1.0));
      sum += w * x;
      const int k = bones.reducedIndex[static_cast<std::size_t>(bones.activeAncestor[j])];
      int slot = 0;
      while (slot < count && targets[slot] != k)
        ++slot;
      if (slot == count) {
        targets[count] = k;
        weights[count] = 0.0;
        means[count] = glm::dvec3(0.0);
        ++count;
      }
      weights[slot] += w;
      means[slot] += w * x;
    }
    if (!baked) // kept as it was, its influences one to one (weights within float rounding)
      continue;
    const glm::dvec3 q(levelMesh.positions[v]);
    drift = std::max(drift, glm::length(q - sum));
    if (count < 2)
      continue;
    double offset = 0.0;
    for (int slot = 0; slot < count; ++slot)
      offset += weights[slot] * glm::length(q - means[slot] / weights[slot]);
    for (int slot = 1; slot < count; ++slot) {
      double& pairOffset = pairOffsets[{targets[0], targets[slot]}];
      pairOffset = std::max(pairOffset, offset);
    }
  }

  // Per frame: how far any vertex may reach.
  // note: frames are independent (each writes its own slot), so stretches of them are
  // measured on every core; the figures do not depend on the split
  const int frames = clip.frameCount;
  std::vector<double> reach(static_cast<std::size_t>(frames));
  constexpr int kStretch = 256; // frames per task
  parallelFor((frames + kStretch - 1) / kStretch, 0, [&](int task) {
    std::vector<glm::mat4> models, levelModels, palette, levelPalette;
    for (int t = task * kStretch; t < std::min(frames, (task + 1) * kStretch); ++t) {
      if (cancelled(cancel))
        return;
      clip.modelMatrices(skeleton, t, models);
      skinningPalette(skeleton, models, palette);
      levelClip.modelMatrices(bones.skeleton, t, levelModels);
      skinningPalette(bones.skeleton, levelModels, levelPalette);
      double bound = 0.0, magnitude = 0.0, levelStretch = 0.0;
      for (std::size_t j = 0; j < m_groups.size(); ++j) {
        if (m_groups[j].empty())
          continue;
        const auto k = static_cast<std::size_t>(bones.reducedIndex[static_cast<std::size_t>(bones.activeAncestor[j])]);
        const glm::dmat4 original(palette[j]);
        const glm::dmat4 level(levelPalette[k]);
        const glm::dmat4 moved = level * glm::dmat4(bake[j]) - original; // D_j
        const double stretch = linearNorm(moved);
        for (const Group& g : m_groups[j])
          bound = std::max(bound, glm::length(glm::dvec3(moved * glm::dvec4(g.centre, 1.0))) + stretch * g.radius);
        const double levelNorm = linearNorm(level);
        levelStretch = std::max(levelStretch, levelNorm);
        magnitude = std::max({magnitude, glm::length(glm::dvec3(original[3])) + linearNorm(original) * m_extent,
                              glm::length(glm::dvec3(level[3])) + levelNorm * levelExtent});
      }
      double blend = 0.0;
      for (const auto& [pair, offset] : pairOffsets)
        blend = std::max(blend, offset * linearNorm(glm::dmat4(levelPalette[std::size_t(pair.second)]) -
                                                    glm::dmat4(levelPalette[std::size_t(pair.first)])));
      const double at = (bound + blend) * (1.0 + 1e-6) + kRoundingMargin * magnitude + 2.0 * levelStretch * drift;
      reach[static_cast<std::size_t>(t)] = std::isnan(at) ? std::numeric_limits<double>::infinity() : at;
    }
  });
  if (cancelled(cancel))
    return Error(kCancelled);

  return reach;
}

Result<double> SkinDeviation::bound(const Skeleton& skeleton, const SkinnedMesh& mesh, const Clip& clip,
                                    const BoneReduction& bones, const SkinnedMesh& levelMesh, const Clip& levelClip,
                                    double floor, const std::atomic<bool>* cancel) const {
  Result<std::vector<double>> reached = reachPerFrame(skeleton, mesh, clip, bones, levelMesh, levelClip, cancel);
  if (!reached)
    return reached.error();
  double largest = floor;
  for (const double r : *reached)
    largest = std::max(largest, r);
  return largest;
}

Result<double> SkinDeviation::measure(const Skeleton& skeleton, const SkinnedMesh& mesh, const Clip& clip,
                                      const BoneReduction& bones, const SkinnedMesh& levelMesh, const Clip& levelClip,
                                      double floor, const std::atomic<bool>* cancel) const {
  Result<std::vector<double>> reached = reachPerFrame(skeleton, mesh, clip, bones, levelMesh, levelClip, cancel);
  if (!reached)
    return reached.error();
  const std::vector<double>& reach = *reached;
  const int frames = clip.frameCount;
  double largest = floor;
  std::vector<glm::mat4> models, levelModels, palette, levelPalette;

  // The frames whose reach passes the largest error so far, farthest first: skinned whole.
  std::vector<int> order(static_cast<std::size_t>(frames));
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const double ra = reach[static_cast<std::size_t>(a)], rb = reach[static_cast<std::size_t>(b)];
    return ra != rb ? ra > rb : a < b;
  });
  std::vector<glm::vec3> original, simplified;
  for (const int t : order) {
    if (!(reach[static_cast<std::size_t>(t)] > largest))
      break;
    if (cancelled(cancel))
      return Error(kCancelled);
    clip.modelMatrices(skeleton, t, models);
    skinningPalette(skeleton, models, palette);
    skinPositions(mesh, palette, original);
    levelClip.modelMatrices(bones.skeleton, t, levelModels);
    skinningPalette(bones.skeleton, levelModels, levelPalette);
    skinPositions(levelMesh, levelPalette, simplified);
    for (std::size_t v = 0; v < original.size(); ++v)
      largest = std::max(largest, double(glm::length(simplified[v] - original[v])));
  }
  return largest;
}

} // namespace mlod
