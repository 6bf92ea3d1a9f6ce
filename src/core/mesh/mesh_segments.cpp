#include "core/mesh/mesh_segments.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cstring>
#include <map>
#include <numeric>
#include <tuple>

namespace mlod {

namespace {

// Bit pattern of a float with -0 read as +0, so that welding compares what a renderer sees.
std::uint32_t floatBits(float value) {
  if (value == 0.0f)
    value = 0.0f;
  std::uint32_t bits = 0;
  std::memcpy(&bits, &value, sizeof bits);
  return bits;
}

using WeldKey = std::array<std::uint32_t, 11>; // position, joints, weights

WeldKey weldKey(const SkinnedMesh& mesh, std::size_t v) {
  WeldKey key{};
  for (int i = 0; i < 3; ++i)
    key[static_cast<std::size_t>(i)] = floatBits(mesh.positions[v][i]);
  if (mesh.skinned())
    for (int i = 0; i < kMaxInfluences; ++i) {
      key[static_cast<std::size_t>(3 + i)] = mesh.joints[v][i];
      key[static_cast<std::size_t>(7 + i)] = floatBits(mesh.weights[v][i]);
    }
  return key;
}

// Every vertex to the lowest index with the same position and influences.
std::vector<std::uint32_t> weldVertices(const SkinnedMesh& mesh, int& out_welded) {
  const std::size_t count = mesh.vertexCount();
  std::vector<WeldKey> keys(count);
  for (std::size_t v = 0; v < count; ++v)
    keys[v] = weldKey(mesh, v);
  std::vector<std::uint32_t> order(count);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return keys[a] < keys[b]; });
  std::vector<std::uint32_t> weld(count);
  out_welded = 0;
  for (std::size_t i = 0; i < count;) {
    std::size_t end = i + 1;
    while (end < count && keys[order[end]] == keys[order[i]])
      ++end;
    for (std::size_t k = i; k < end; ++k)
      weld[order[k]] = order[i]; // stable sort: order[i] is the lowest index of the group
    ++out_welded;
    i = end;
  }
  return weld;
}

int triangleSegmentJoint(const SkinnedMesh& mesh, const std::vector<std::uint8_t>& shared, std::size_t triangle) {
  int joint = -1;
  for (int k = 0; k < 3; ++k) {
    const std::uint32_t v = mesh.indices[triangle * 3 + static_cast<std::size_t>(k)];
    if (!shared[v]) {
      const int j = mesh.joints[v].x;
      joint = joint < 0 ? j : std::min(joint, j);
    }
  }
  if (joint >= 0)
    return joint;
  // every vertex shared: the joint that dominates most of them
  std::array<int, 3> dominant{};
  for (int k = 0; k < 3; ++k)
    dominant[static_cast<std::size_t>(k)] = mesh.joints[mesh.indices[triangle * 3 + static_cast<std::size_t>(k)]].x;
  std::sort(dominant.begin(), dominant.end());
  if (dominant[1] == dominant[2])
    return dominant[1];
  return dominant[0]; // all three differ, or the two lowest agree
}

} // namespace

MeshSegmentation segmentMesh(const SkinnedMesh& mesh) {
  MeshSegmentation out;
  const std::size_t vertexCount = mesh.vertexCount();
  const std::size_t triangleCount = mesh.triangleCount();
  out.weld = weldVertices(mesh, out.weldedVertices);

  out.shared.assign(vertexCount, 0);
  if (mesh.skinned())
    for (std::size_t v = 0; v < vertexCount; ++v) {
      const glm::vec4& w = mesh.weights[v];
      for (int i = 0; i < kMaxInfluences; ++i)
        if (w[i] > 0.0f && w[i] < 1.0f)
          out.shared[v] = 1;
    }

  // segments, in ascending joint order
  std::vector<int> triangleJoint(triangleCount, -1);
  std::map<int, int> segmentOfJoint;
  for (std::size_t t = 0; t < triangleCount; ++t) {
    triangleJoint[t] = mesh.skinned() ? triangleSegmentJoint(mesh, out.shared, t) : -1;
    segmentOfJoint.emplace(triangleJoint[t], 0);
  }
  for (auto& [joint, index] : segmentOfJoint) {
    index = static_cast<int>(out.segments.size());
    out.segments.push_back(MeshSegment{joint, {}});
  }
  out.triangleSegment.resize(triangleCount);
  for (std::size_t t = 0; t < triangleCount; ++t) {
    const int segment = segmentOfJoint[triangleJoint[t]];
    out.triangleSegment[t] = segment;
    out.segments[static_cast<std::size_t>(segment)].triangles.push_back(static_cast<std::uint32_t>(t));
  }

  // locks on welded vertices
  std::vector<std::uint8_t> lockedWelded(vertexCount, 0);
  for (std::size_t v = 0; v < vertexCount; ++v)
    if (out.shared[v])
      lockedWelded[out.weld[v]] = 1;
  std::vector<int> segmentOfVertex(vertexCount, -1);
  std::vector<std::tuple<int, std::uint32_t, std::uint32_t>> edges; // (segment, lower, higher) welded
  edges.reserve(triangleCount * 3);
  for (std::size_t t = 0; t < triangleCount; ++t) {
    const int segment = out.triangleSegment[t];
    std::array<std::uint32_t, 3> corner{};
    for (int k = 0; k < 3; ++k)
      corner[static_cast<std::size_t>(k)] = out.weld[mesh.indices[t * 3 + static_cast<std::size_t>(k)]];
    const bool degenerate = corner[0] == corner[1] || corner[1] == corner[2] || corner[0] == corner[2];
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = corner[static_cast<std::size_t>(k)];
      const std::uint32_t b = corner[static_cast<std::size_t>((k + 1) % 3)];
      if (degenerate)
        lockedWelded[a] = 1; // the decimater cannot hold such a triangle: keep it as it is
      int& owner = segmentOfVertex[a];
      if (owner < 0)
        owner = segment;
      else if (owner != segment)
        lockedWelded[a] = 1; // used by two segments
      if (!degenerate)
        edges.emplace_back(segment, std::min(a, b), std::max(a, b));
    }
  }
  std::sort(edges.begin(), edges.end());
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t end = i + 1;
    while (end < edges.size() && edges[end] == edges[i])
      ++end;
    if (end - i != 2) { // a border edge (1) or a non-manifold one (3 or more)
      lockedWelded[std::get<1>(edges[i])] = 1;
      lockedWelded[std::get<2>(edges[i])] = 1;
    }
    i = end;
  }

  out.locked.assign(vertexCount, 0);
  for (std::size_t v = 0; v < vertexCount; ++v) {
    out.locked[v] = lockedWelded[out.weld[v]];
    out.sharedVertices += out.shared[v];
    out.lockedVertices += out.locked[v];
  }
  return out;
}

} // namespace mlod
