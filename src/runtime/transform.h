#pragma once
// An affine joint transform split into translation, rotation and scale, and the
// helpers that turn it into a matrix. Lengths are in centimetres throughout the
// runtime; rotations are unit quaternions.

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace mlod {

struct Transform {
  glm::vec3 translation{0.0f};             // cm
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f}; // unit quaternion (w, x, y, z)
  glm::vec3 scale{1.0f};

  // True when every component is finite and the rotation has unit length within `tolerance`.
  bool isValid(float tolerance = 1e-3f) const;
};

// Matrix T * R * S: scale first, then rotation, then translation.
glm::mat4 toMatrix(const Transform& transform);

// Decomposes an affine matrix without shear into translation, rotation and scale.
// A negative determinant is folded into the x scale.
Transform decompose(const glm::mat4& matrix);

} // namespace mlod
