#pragma once
// A triangle mesh with up to four joint influences per vertex. Positions in cm,
// in the model space of the asset's skeleton at bind time.

#include "core/error.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace mlod {

inline constexpr int kMaxInfluences = 4;

// One source mesh inside a merged mesh: a range of triangles.
struct MeshPart {
  std::string name;
  std::uint32_t firstIndex = 0; // into SkinnedMesh::indices
  std::uint32_t indexCount = 0; // a multiple of 3
};

class SkinnedMesh {
public:
  std::string name;
  std::vector<glm::vec3> positions;    // cm
  std::vector<glm::vec3> normals;      // unit, or empty
  std::vector<glm::vec2> uvs;          // or empty
  std::vector<std::uint32_t> indices;  // triangles
  // Influences: empty for a static mesh; else one entry per vertex, sorted by
  // weight (largest first), unused slots (joint 0, weight 0).
  std::vector<glm::u16vec4> joints;
  std::vector<glm::vec4> weights;
  std::vector<MeshPart> parts;

  bool skinned() const { return !weights.empty(); }
  std::size_t vertexCount() const { return positions.size(); }
  std::size_t triangleCount() const { return indices.size() / 3; }
  // Number of distinct joints that influence some vertex.
  int boneCount() const;

  // Rules: at least one vertex and one triangle; indices in range, a multiple of 3;
  // normals and uvs empty or one per vertex; positions, normals, uvs finite; for a
  // skinned mesh one influence set per vertex, joints < jointCount, weights finite,
  // >= 0, sorted largest first, summing to exactly 1.0f (w.x + w.y + w.z + w.w in
  // float); parts cover index ranges inside the mesh.
  Error validate(int jointCount) const;
};

// Keeps the `kMaxInfluences` largest of `count` influences, sorted largest first, with
// weights scaled so that their float sum (x + y + z + w, in that order) is exactly 1.
// Returns false when no weight is positive (the caller decides what such a vertex binds to).
bool normalizeInfluences(const int* joints, const float* weights, int count, glm::u16vec4& out_joints,
                         glm::vec4& out_weights);

} // namespace mlod
