#pragma once
// The viewports' camera: orbits a target point (yaw about +Y, pitch), dollies towards it,
// pans across the view, flies (moves the target along the view). Lengths in cm.

#include <glm/glm.hpp>

namespace mlod {

class OrbitCamera {
public:
  glm::vec3 target{0.0f, 90.0f, 0.0f};
  float yawRadians = 0.6f;    // about +Y, 0 = looking along -Z
  float pitchRadians = -0.25f; // negative looks down
  float distance = 400.0f;    // cm from the target
  float verticalFovRadians = 0.7854f; // 45 degrees

  glm::vec3 eye() const;
  glm::vec3 forward() const; // unit, from the eye to the target
  glm::mat4 view() const;
  glm::mat4 projection(float aspect) const; // near/far follow the distance
  glm::mat4 viewProjection(float aspect) const { return projection(aspect) * view(); }

  void orbit(float dxPixels, float dyPixels);
  void pan(float dxPixels, float dyPixels, float viewportHeightPixels);
  void dolly(float steps);                     // > 0 closer; one wheel notch = 1
  void fly(const glm::vec3& stepInView);       // x right, y up, z forward, cm
  // Aims at the box and backs off so that it fills the view.
  void frame(const glm::vec3& lo, const glm::vec3& hi);
  // Window coordinates (pixels, y down) of a world point; false behind the camera.
  bool project(const glm::vec3& world, float width, float height, glm::vec2& out_pixel) const;
};

} // namespace mlod
