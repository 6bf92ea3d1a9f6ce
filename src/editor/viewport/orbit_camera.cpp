#include "editor/viewport/orbit_camera.h"

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace mlod {

glm::vec3 OrbitCamera::forward() const {
  return glm::vec3(-std::sin(yawRadians) * std::cos(pitchRadians), std::sin(pitchRadians),
                   -std::cos(yawRadians) * std::cos(pitchRadians));
}

glm::vec3 OrbitCamera::eye() const { return target - distance * forward(); }

glm::mat4 OrbitCamera::view() const { return glm::lookAt(eye(), target, glm::vec3(0.0f, 1.0f, 0.0f)); }

glm::mat4 OrbitCamera::projection(float aspect) const {
  const float nearPlane = std::max(1.0f, 0.01f * distance);
  const float farPlane = std::max(100000.0f, 1000.0f * distance);
  return glm::perspective(verticalFovRadians, aspect > 0.0f ? aspect : 1.0f, nearPlane, farPlane);
}

void OrbitCamera::orbit(float dxPixels, float dyPixels) {
  yawRadians -= 0.008f * dxPixels;
  pitchRadians = std::clamp(pitchRadians - 0.008f * dyPixels, -1.5f, 1.5f);
}

void OrbitCamera::pan(float dxPixels, float dyPixels, float viewportHeightPixels) {
  const float perPixel = 2.0f * distance * std::tan(0.5f * verticalFovRadians) / std::max(1.0f, viewportHeightPixels);
  const glm::vec3 right = glm::normalize(glm::cross(forward(), glm::vec3(0.0f, 1.0f, 0.0f)));
  const glm::vec3 up = glm::cross(right, forward());
  target += (-dxPixels * right + dyPixels * up) * perPixel;
}

void OrbitCamera::dolly(float steps) { distance = std::clamp(distance * std::pow(0.85f, steps), 1.0f, 1.0e6f); }

void OrbitCamera::fly(const glm::vec3& stepInView) {
  const glm::vec3 f = forward();
  const glm::vec3 right = glm::normalize(glm::cross(f, glm::vec3(0.0f, 1.0f, 0.0f)));
  target += stepInView.x * right + stepInView.y * glm::vec3(0.0f, 1.0f, 0.0f) + stepInView.z * f;
}

void OrbitCamera::frame(const glm::vec3& lo, const glm::vec3& hi) {
  target = 0.5f * (lo + hi);
  const float radius = std::max(1.0f, 0.5f * glm::length(hi - lo));
  distance = radius / std::sin(0.5f * verticalFovRadians) * 1.05f;
}

bool OrbitCamera::project(const glm::vec3& world, float width, float height, glm::vec2& out_pixel) const {
  const glm::vec4 clip = viewProjection(width / std::max(1.0f, height)) * glm::vec4(world, 1.0f);
  if (clip.w <= 0.0f)
    return false;
  const glm::vec3 ndc = glm::vec3(clip) / clip.w;
  out_pixel = glm::vec2((ndc.x * 0.5f + 0.5f) * width, (1.0f - (ndc.y * 0.5f + 0.5f)) * height);
  return true;
}

} // namespace mlod
