#pragma once
// Converts local joint matrices to model space by walking the hierarchy once.
// A job in the ozz style: fill the inputs, check validate(), call run(). It never
// allocates; the caller owns every buffer.

#include <glm/glm.hpp>

#include <cstdint>
#include <span>

namespace mlod {

struct LocalToModelJob {
  // Parent index per joint, parent before child; -1 for a root. Joint count = parents.size().
  std::span<const std::int16_t> parents;
  // Local matrices, one per joint (cm).
  std::span<const glm::mat4> locals;
  // Optional transform applied above every root (identity when absent).
  const glm::mat4* root = nullptr;
  // Output: model-space matrices, one per joint.
  std::span<glm::mat4> out_models;

  // Rules: locals and out_models hold one entry per joint; every parent index is
  // -1 or smaller than its joint's index; at most 32767 joints.
  bool validate() const;
  // Returns false (and writes nothing) when validate() fails.
  bool run() const;
};

} // namespace mlod
