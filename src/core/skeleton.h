#pragma once
// A joint hierarchy in parent-before-child order, with its rest (bind) pose.
// Lengths in cm. Leaves such as BVH "End Site"s are joints too.

#include "core/error.h"
#include "runtime/transform.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace mlod {

struct Joint {
  std::string name;
  int parent = -1;              // index of the parent joint, -1 for the root
  Transform rest;               // rest local transform relative to the parent (cm)
  // Mesh space -> joint space at bind time, where a mesh is bound to this joint (cm).
  std::optional<glm::mat4> inverseBind;
};

class Skeleton {
public:
  std::vector<Joint> joints;

  int jointCount() const { return static_cast<int>(joints.size()); }
  bool empty() const { return joints.empty(); }
  // Index of the joint with this exact name, or -1.
  int find(const std::string& name) const;
  // Indices of the direct children of `joint`, in order.
  std::vector<int> children(int joint) const;
  // Parent indices as the runtime's jobs take them.
  std::vector<std::int16_t> parentIndices() const;
  // Model-space rest matrices (forward kinematics of the rest pose).
  std::vector<glm::mat4> restModelMatrices() const;
  // Joints without children.
  int leafCount() const;

  // Rules: at most 32,767 joints; exactly one root, at index 0; every other parent
  // index is smaller than its joint's index (parent before child); names are non-empty
  // and unique; rest transforms are finite with unit rotations; inverse bind matrices
  // are finite and invertible.
  Error validate() const;
};

} // namespace mlod
