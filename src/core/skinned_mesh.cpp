#include "core/skinned_mesh.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>

namespace mlod {

namespace {
float floatSum(const glm::vec4& w) { return ((w.x + w.y) + w.z) + w.w; }

// Sets w.x so that floatSum(w) is exactly 1, searching outward from the real-valued
// answer one ulp at a time (the float sum is monotone in w.x). False when no value lands.
bool solveLargest(glm::vec4& w) {
  const float start = 1.0f - ((w.y + w.z) + w.w);
  float up = start;
  float down = start;
  for (int step = 0; step < 256; ++step) {
    w.x = up;
    if (floatSum(w) == 1.0f)
      return true;
    w.x = down;
    if (floatSum(w) == 1.0f)
      return true;
    up = std::nextafter(up, 2.0f);
    down = std::nextafter(down, 0.0f);
  }
  w.x = start;
  return false;
}
} // namespace

bool normalizeInfluences(const int* joints, const float* weights, int count, glm::u16vec4& out_joints,
                         glm::vec4& out_weights) {
  std::vector<int> order(static_cast<std::size_t>(count));
  std::iota(order.begin(), order.end(), 0);
  // Stable, so equal weights keep the source's order and the result is deterministic.
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return weights[a] > weights[b]; });
  const int kept = std::min(count, kMaxInfluences);
  double total = 0.0;
  for (int i = 0; i < kept; ++i)
    total += std::max(0.0f, weights[order[static_cast<std::size_t>(i)]]);
  out_joints = glm::u16vec4(0);
  out_weights = glm::vec4(0.0f);
  if (!(total > 0.0) || !std::isfinite(total))
    return false;
  for (int i = 0; i < kept; ++i) {
    const int k = order[static_cast<std::size_t>(i)];
    const float w = std::max(0.0f, weights[k]);
    if (w == 0.0f)
      break;
    out_joints[i] = static_cast<std::uint16_t>(joints[k]);
    out_weights[i] = static_cast<float>(w / total);
  }
  // note: rounding each weight to float leaves a residual of a few ulps; it goes into
  // the largest weight, where it matters least. With ties (three weights of 1/3) the
  // largest can end an ulp below the next: then the later ones come down to it and the
  // largest takes the residual again, so the result stays sorted.
  for (int attempt = 0; attempt < 32; ++attempt) {
    if (!solveLargest(out_weights)) {
      // note: x + y can fall only on every other float (y an odd multiple of half x's
      // ulp, ties to even), so that no x reaches 1; an ulp off y changes that.
      const int i = out_weights.z > 0.0f && attempt % 2 == 1 ? 2 : 1;
      out_weights[i] = std::nextafter(out_weights[i], 0.0f);
      continue;
    }
    bool sorted = true;
    for (int i = 1; i < kMaxInfluences; ++i)
      if (out_weights[i] > out_weights[i - 1]) {
        out_weights[i] = out_weights[i - 1];
        sorted = false;
      }
    if (sorted)
      break;
  }
  return true;
}

int SkinnedMesh::boneCount() const {
  std::set<std::uint16_t> used;
  for (std::size_t v = 0; v < joints.size(); ++v)
    for (int i = 0; i < kMaxInfluences; ++i)
      if (weights[v][i] > 0.0f)
        used.insert(joints[v][i]);
  return static_cast<int>(used.size());
}

Error SkinnedMesh::validate(int jointCount) const {
  const std::string where = "mesh '" + name + "'";
  const std::size_t n = positions.size();
  if (n == 0 || indices.empty())
    return Error(where + " has no vertices or no triangles");
  if (indices.size() % 3 != 0)
    return Error(where + " has an index count that is not a multiple of 3");
  for (std::uint32_t index : indices)
    if (index >= n)
      return Error(where + " has a vertex index " + std::to_string(index) + " out of range (" +
                   std::to_string(n) + " vertices)");
  if ((!normals.empty() && normals.size() != n) || (!uvs.empty() && uvs.size() != n))
    return Error(where + " has normals or uvs that do not match its vertex count");
  for (const glm::vec3& p : positions)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      return Error(where + " has a non-finite vertex position");
  for (const glm::vec3& p : normals)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      return Error(where + " has a non-finite normal");
  for (const glm::vec2& p : uvs)
    if (!std::isfinite(p.x) || !std::isfinite(p.y))
      return Error(where + " has a non-finite texture coordinate");
  if (joints.size() != weights.size() || (!weights.empty() && weights.size() != n))
    return Error(where + " has skin influences that do not match its vertex count");
  for (std::size_t v = 0; v < weights.size(); ++v) {
    const glm::vec4& w = weights[v];
    for (int i = 0; i < kMaxInfluences; ++i) {
      if (!std::isfinite(w[i]) || w[i] < 0.0f)
        return Error(where + " has an invalid skin weight at vertex " + std::to_string(v));
      if (joints[v][i] >= jointCount)
        return Error(where + " binds vertex " + std::to_string(v) + " to joint " + std::to_string(joints[v][i]) +
                     ", which does not exist");
      if (i > 0 && w[i] > w[i - 1])
        return Error(where + " has influences not sorted by weight at vertex " + std::to_string(v));
    }
    if (floatSum(w) != 1.0f)
      return Error(where + " has skin weights that do not sum to 1 at vertex " + std::to_string(v));
  }
  for (const MeshPart& part : parts)
    if (part.indexCount % 3 != 0 || std::size_t{part.firstIndex} + part.indexCount > indices.size())
      return Error(where + " has a part '" + part.name + "' outside its index range");
  return {};
}

} // namespace mlod
