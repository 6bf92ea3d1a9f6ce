#pragma once
// Linear blend skinning (LBS) of positions and normals, with the palette the pose evaluator
// writes (palette_j = model_j x inverse bind_j, cm):
//     p' = (sum_i w_i P[j_i]) (p, 1)     n' = (sum_i w_i P[j_i]) (n, 0)
// Normals are not renormalised (as ozz's SkinningJob; renormalise in the shader). Vertices
// are processed in batches of one influence count (1 to 4), so a vertex bound to one joint
// costs one matrix-vector product and no blending: SkinningMesh sorts a mesh that way.

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace mlod {

struct SkinningJob {
  int influences = 1; // 1 to 4: every vertex of the batch has exactly this many
  std::span<const glm::mat4> palette; // affine (bottom row 0 0 0 1), one per joint
  // Per vertex, `influences` joint indices (each < palette.size(): checked by
  // SkinningMesh::build(), not here, where it would cost as much as skinning) and weights
  // summing to 1. With one influence, weights may be empty (the weight is 1).
  std::span<const std::uint16_t> joints;
  std::span<const float> weights;
  std::span<const glm::vec3> positions; // cm, bind pose
  std::span<const glm::vec3> normals;   // may be empty
  std::span<glm::vec3> out_positions;   // one per vertex
  std::span<glm::vec3> out_normals;     // one per vertex; empty exactly when normals is

  // Rules: influences in [1, 4]; a palette; joints vertices x influences; weights the same
  // or (one influence) empty; out_positions one per vertex; normals and out_normals both
  // empty or both one per vertex.
  bool validate() const;
  // Returns false (and writes nothing) when validate() fails.
  bool run() const;
};

// A skinned mesh reordered for SkinningJob: vertices grouped by influence count (1, 2, 3,
// 4), in source order inside each group. Built once per mesh.
class SkinningMesh {
public:
  // Influences as core's SkinnedMesh holds them: up to four per vertex, sorted by weight,
  // largest first, unused slots weight 0. A vertex's influence count is the number of
  // positive weights. Errors: sizes that differ, a vertex without a positive weight, a
  // joint index >= jointCount, weights that are not finite.
  static std::optional<SkinningMesh> build(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
                                           std::span<const glm::u16vec4> joints, std::span<const glm::vec4> weights,
                                           int jointCount, std::string* out_error = nullptr);

  int vertexCount() const { return static_cast<int>(m_order.size()); }
  int jointCount() const { return m_jointCount; }
  bool hasNormals() const { return !m_normals.empty(); }
  // Source vertex of each vertex here: out_positions[i] is source vertex order()[i].
  std::span<const std::uint32_t> order() const { return m_order; }
  // Vertices with `influences` influences: [groupBegin(k), groupBegin(k + 1)), k in 1..4.
  int groupBegin(int influences) const { return m_groupBegin[static_cast<std::size_t>(influences - 1)]; }
  std::size_t byteSize() const;

  // The job of one influence group, writing into out_positions / out_normals (vertexCount()
  // each, in this mesh's order; out_normals empty when the mesh has none).
  SkinningJob job(int influences, std::span<const glm::mat4> palette, std::span<glm::vec3> out_positions,
                  std::span<glm::vec3> out_normals) const;
  // All four groups. False when a job does not validate (palette smaller than jointCount(),
  // wrong output sizes).
  bool skin(std::span<const glm::mat4> palette, std::span<glm::vec3> out_positions,
            std::span<glm::vec3> out_normals) const;

private:
  int m_jointCount = 0;
  std::vector<std::uint32_t> m_order;
  int m_groupBegin[5] = {0, 0, 0, 0, 0};
  std::vector<glm::vec3> m_positions;
  std::vector<glm::vec3> m_normals;
  std::vector<std::uint16_t> m_joints;  // group by group, k per vertex
  std::vector<float> m_weights;         // group by group, k per vertex (none for group 1)
  std::size_t m_influenceBegin[4] = {0, 0, 0, 0}; // where each group starts in m_joints
  std::size_t m_weightBegin[4] = {0, 0, 0, 0};
};

} // namespace mlod
