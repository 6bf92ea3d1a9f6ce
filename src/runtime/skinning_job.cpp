#include "runtime/skinning_job.h"

#include <cmath>
#include <cstring>
#include <glm/gtc/type_ptr.hpp>

// The hot loops are also compiled for x86-64-v3 (AVX2, FMA) and picked at load time.
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__)) && !defined(MLOD_NO_TARGET_CLONES)
#define MLOD_RUNTIME_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define MLOD_RUNTIME_CLONES
#endif

namespace mlod {

namespace {

typedef float v4 __attribute__((vector_size(16)));

inline v4 load4(const float* p) {
  v4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
inline void store3(glm::vec3& out, v4 v) {
  out.x = v[0];
  out.y = v[1];
  out.z = v[2];
}
// 16 bytes at `out`: its 3 floats and the next vector's x, which the next vertex rewrites
// (one store instead of a spill and two).
inline void store3Over(glm::vec3& out, v4 v) {
  std::memcpy(&out, &v, sizeof v);
}

// One influence count: the blended matrix's columns c0..c3, then p' and n'. Every vertex
// but the last of the batch is stored 16 bytes wide (see store3Over()).
template <int K, bool Normals>
__attribute__((always_inline)) inline void
skinLoop(const glm::mat4* __restrict palette, const std::uint16_t* __restrict joints, const float* __restrict weights,
         const glm::vec3* __restrict positions, const glm::vec3* __restrict normals, glm::vec3* __restrict outPositions,
         glm::vec3* __restrict outNormals, std::size_t count) {
  const auto vertex = [&](std::size_t v, auto store) {
    const float* m = glm::value_ptr(palette[joints[0]]);
    v4 c0 = load4(m), c1 = load4(m + 4), c2 = load4(m + 8), c3 = load4(m + 12);
    if constexpr (K > 1) {
      const float w0 = weights[0];
      c0 *= w0;
      c1 *= w0;
      c2 *= w0;
      c3 *= w0;
      for (int i = 1; i < K; ++i) {
        const float* n = glm::value_ptr(palette[joints[i]]);
        const float w = weights[i];
        c0 += load4(n) * w;
        c1 += load4(n + 4) * w;
        c2 += load4(n + 8) * w;
        c3 += load4(n + 12) * w;
      }
      weights += K;
    }
    joints += K;
    const glm::vec3 p = positions[v];
    // (c3 first: three multiply-adds)
    store(outPositions[v], c3 + c0 * p.x + c1 * p.y + c2 * p.z);
    if constexpr (Normals) {
      const glm::vec3 n = normals[v];
      store(outNormals[v], c0 * n.x + c1 * n.y + c2 * n.z);
    }
  };
  if (count == 0)
    return;
  for (std::size_t v = 0; v + 1 < count; ++v)
    vertex(v, [](glm::vec3& out, v4 value) { store3Over(out, value); });
  vertex(count - 1, [](glm::vec3& out, v4 value) { store3(out, value); });
}

template <int K> __attribute__((always_inline)) inline void skinGroup(const SkinningJob& job) {
  const std::size_t count = job.positions.size();
  if (job.normals.empty())
    skinLoop<K, false>(job.palette.data(), job.joints.data(), job.weights.data(), job.positions.data(), nullptr,
                       job.out_positions.data(), nullptr, count);
  else
    skinLoop<K, true>(job.palette.data(), job.joints.data(), job.weights.data(), job.positions.data(),
                      job.normals.data(), job.out_positions.data(), job.out_normals.data(), count);
}

MLOD_RUNTIME_CLONES
void skin(const SkinningJob& job) {
  switch (job.influences) {
  case 1:
    skinGroup<1>(job);
    break;
  case 2:
    skinGroup<2>(job);
    break;
  case 3:
    skinGroup<3>(job);
    break;
  default:
    skinGroup<4>(job);
    break;
  }
}

bool fail(std::string* out_error, const std::string& message) {
  if (out_error)
    *out_error = message;
  return false;
}

} // namespace

bool SkinningJob::validate() const {
  if (influences < 1 || influences > 4 || palette.empty())
    return false;
  const std::size_t vertices = positions.size();
  const std::size_t k = static_cast<std::size_t>(influences);
  if (joints.size() != vertices * k)
    return false;
  if (weights.size() != vertices * k && !(influences == 1 && weights.empty()))
    return false;
  if (out_positions.size() != vertices)
    return false;
  if (normals.empty() != out_normals.empty())
    return false;
  if (!normals.empty() && (normals.size() != vertices || out_normals.size() != vertices))
    return false;
  return true;
}

bool SkinningJob::run() const {
  if (!validate())
    return false;
  skin(*this);
  return true;
}

std::optional<SkinningMesh> SkinningMesh::build(std::span<const glm::vec3> positions,
                                                std::span<const glm::vec3> normals,
                                                std::span<const glm::u16vec4> joints,
                                                std::span<const glm::vec4> weights, int jointCount,
                                                std::string* out_error) {
  const std::size_t vertices = positions.size();
  if (vertices == 0) {
    fail(out_error, "the mesh has no vertices");
    return std::nullopt;
  }
  if (vertices > 0xffffffffu || joints.size() != vertices || weights.size() != vertices ||
      (!normals.empty() && normals.size() != vertices)) {
    fail(out_error, "positions, normals (or none), joints and weights must hold one entry per vertex");
    return std::nullopt;
  }
  if (jointCount < 1 || jointCount > 65536) {
    fail(out_error, "joint count " + std::to_string(jointCount) + " is not in [1, 65536]");
    return std::nullopt;
  }
  // the positive influences of each vertex, in the order given
  std::vector<std::uint8_t> counts(vertices);
  for (std::size_t v = 0; v < vertices; ++v) {
    int count = 0;
    for (int i = 0; i < 4; ++i) {
      const float w = weights[v][i];
      if (!std::isfinite(w) || w < 0.0f) {
        fail(out_error, "vertex " + std::to_string(v) + " has a weight that is negative or not finite");
        return std::nullopt;
      }
      if (w > 0.0f) {
        if (joints[v][i] >= jointCount) {
          fail(out_error, "vertex " + std::to_string(v) + " names joint " + std::to_string(joints[v][i]) + " of " +
                              std::to_string(jointCount));
          return std::nullopt;
        }
        ++count;
      }
    }
    if (count == 0) {
      fail(out_error, "vertex " + std::to_string(v) + " has no positive weight");
      return std::nullopt;
    }
    counts[v] = static_cast<std::uint8_t>(count);
  }
  SkinningMesh mesh;
  mesh.m_jointCount = jointCount;
  mesh.m_order.reserve(vertices);
  for (int k = 1; k <= 4; ++k) {
    mesh.m_groupBegin[k - 1] = static_cast<int>(mesh.m_order.size());
    mesh.m_influenceBegin[k - 1] = mesh.m_joints.size();
    mesh.m_weightBegin[k - 1] = mesh.m_weights.size();
    for (std::size_t v = 0; v < vertices; ++v) {
      if (counts[v] != k)
        continue;
      mesh.m_order.push_back(static_cast<std::uint32_t>(v));
      for (int i = 0; i < 4; ++i)
        if (weights[v][i] > 0.0f) {
          mesh.m_joints.push_back(joints[v][i]);
          if (k > 1)
            mesh.m_weights.push_back(weights[v][i]);
        }
    }
  }
  mesh.m_groupBegin[4] = static_cast<int>(mesh.m_order.size());
  mesh.m_positions.reserve(vertices);
  for (std::uint32_t v : mesh.m_order)
    mesh.m_positions.push_back(positions[v]);
  if (!normals.empty()) {
    mesh.m_normals.reserve(vertices);
    for (std::uint32_t v : mesh.m_order)
      mesh.m_normals.push_back(normals[v]);
  }
  return mesh;
}

std::size_t SkinningMesh::byteSize() const {
  return sizeof(SkinningMesh) + m_order.size() * sizeof(std::uint32_t) + m_positions.size() * sizeof(glm::vec3) +
         m_normals.size() * sizeof(glm::vec3) + m_joints.size() * sizeof(std::uint16_t) +
         m_weights.size() * sizeof(float);
}

SkinningJob SkinningMesh::job(int influences, std::span<const glm::mat4> palette, std::span<glm::vec3> out_positions,
                              std::span<glm::vec3> out_normals) const {
  const std::size_t begin = static_cast<std::size_t>(groupBegin(influences));
  const std::size_t count = static_cast<std::size_t>(groupBegin(influences + 1)) - begin;
  const std::size_t k = static_cast<std::size_t>(influences);
  SkinningJob job;
  job.influences = influences;
  job.palette = palette;
  job.joints = std::span<const std::uint16_t>(m_joints).subspan(m_influenceBegin[k - 1], count * k);
  if (influences > 1)
    job.weights = std::span<const float>(m_weights).subspan(m_weightBegin[k - 1], count * k);
  job.positions = std::span<const glm::vec3>(m_positions).subspan(begin, count);
  if (!m_normals.empty())
    job.normals = std::span<const glm::vec3>(m_normals).subspan(begin, count);
  if (out_positions.size() >= begin + count)
    job.out_positions = out_positions.subspan(begin, count);
  if (!out_normals.empty() && out_normals.size() >= begin + count)
    job.out_normals = out_normals.subspan(begin, count);
  return job;
}

bool SkinningMesh::skin(std::span<const glm::mat4> palette, std::span<glm::vec3> out_positions,
                        std::span<glm::vec3> out_normals) const {
  const std::size_t vertices = m_order.size();
  if (palette.size() < static_cast<std::size_t>(m_jointCount) || out_positions.size() != vertices ||
      out_normals.size() != (m_normals.empty() ? 0 : vertices))
    return false;
  for (int k = 1; k <= 4; ++k) {
    if (groupBegin(k) == groupBegin(k + 1))
      continue;
    if (!job(k, palette, out_positions, out_normals).run())
      return false;
  }
  return true;
}

} // namespace mlod
