#pragma once
// Which LOD level a character plays. Ahn & Wohn control "the detail of the motion and the
// geometry by the distance between the camera and the character's position" (section
// 6.2); docs/architecture.md section 3 adds the projected size on screen. Both switch with hysteresis,
// so that a character standing near a boundary does not flicker between two levels.
//
// Levels: 0 is the finest. `boundaries` has one entry per switch (levels - 1 entries).
// Hysteresis h (a fraction, e.g. 0.1): a character moves to the coarser level past a
// boundary only once it is beyond it by h (distance > b (1 + h), or size < s (1 - h)),
// and back only once it is inside by h (distance < b (1 - h), or size > s (1 + h)).
// Without a current level (-1) the level is the plain one, with no hysteresis.

#include <glm/glm.hpp>

#include <cstdint>
#include <span>

namespace mlod {

// Level by camera distance (cm). `switchDistances` ascending, > 0: level i is used between
// switchDistances[i - 1] and switchDistances[i].
int selectLevelByDistance(float distance, std::span<const float> switchDistances, int currentLevel = -1,
                          float hysteresis = 0.1f);

// The projection that screen sizes assume (docs/architecture.md section 3: 60 degrees vertical field of
// view, 1080 pixels high, by default).
struct ScreenProjection {
  float verticalFovRadians = 1.04719755f; // 60 degrees
  float viewportHeightPixels = 1080.0f;
};

// Height in pixels that a sphere of `radius` (cm) at `distance` (cm, > 0) covers on screen:
// its diameter over the visible height at that distance.
float projectedSizePixels(float radius, float distance, const ScreenProjection& projection = {});

// Level by projected size (pixels). `switchSizes` descending, > 0: level i is used while
// the size is below switchSizes[i - 1] and at or above switchSizes[i].
int selectLevelByScreenSize(float sizePixels, std::span<const float> switchSizes, int currentLevel = -1,
                            float hysteresis = 0.1f);

// A crowd at once: every character's level from its position and bounding radius.
struct LodSelectionJob {
  enum class Mode : std::uint8_t { Distance, ScreenSize };
  Mode mode = Mode::Distance;
  glm::vec3 camera{0.0f};                // cm
  std::span<const glm::vec3> positions;  // character centres, cm
  std::span<const float> radii;          // bounding-sphere radii, cm (ScreenSize mode only; one per character)
  std::span<const float> boundaries;     // switchDistances (Distance) or switchSizes (ScreenSize)
  float hysteresis = 0.1f;               // [0, 1)
  ScreenProjection projection;
  // In: each character's current level (-1 = none yet); out: its new level.
  std::span<std::int32_t> inout_levels;

  // Rules: positions and inout_levels one per character (radii too in ScreenSize mode);
  // boundaries finite, > 0 and ascending (Distance) or descending (ScreenSize); hysteresis
  // in [0, 1); the projection's field of view in (0, pi) and height > 0; current levels in
  // [-1, boundaries.size()].
  bool validate() const;
  bool run() const;
};

} // namespace mlod
