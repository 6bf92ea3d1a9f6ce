#include "runtime/transform.h"

#include <cmath>

namespace mlod {

namespace {
bool isFinite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
} // namespace

bool Transform::isValid(float tolerance) const {
  if (!isFinite(translation) || !isFinite(scale))
    return false;
  if (!std::isfinite(rotation.x) || !std::isfinite(rotation.y) || !std::isfinite(rotation.z) ||
      !std::isfinite(rotation.w))
    return false;
  return std::abs(glm::length(rotation) - 1.0f) <= tolerance;
}

glm::mat4 toMatrix(const Transform& transform) {
  glm::mat4 m = glm::mat4_cast(transform.rotation);
  m[0] *= transform.scale.x;
  m[1] *= transform.scale.y;
  m[2] *= transform.scale.z;
  m[3] = glm::vec4(transform.translation, 1.0f);
  return m;
}

Transform decompose(const glm::mat4& matrix) {
  Transform out;
  out.translation = glm::vec3(matrix[3]);
  glm::vec3 axes[3] = {glm::vec3(matrix[0]), glm::vec3(matrix[1]), glm::vec3(matrix[2])};
  out.scale = {glm::length(axes[0]), glm::length(axes[1]), glm::length(axes[2])};
  // note: a mirrored basis cannot be a rotation; the mirror goes into the x scale.
  if (glm::dot(glm::cross(axes[0], axes[1]), axes[2]) < 0.0f)
    out.scale.x = -out.scale.x;
  glm::mat3 rotation(1.0f);
  for (int i = 0; i < 3; ++i)
    if (out.scale[i] != 0.0f)
      rotation[i] = axes[i] / out.scale[i];
  out.rotation = glm::normalize(glm::quat_cast(rotation));
  return out;
}

} // namespace mlod
