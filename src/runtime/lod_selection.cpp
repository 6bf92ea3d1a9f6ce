#include "runtime/lod_selection.h"

#include <algorithm>
#include <cmath>

namespace mlod {

namespace {

// Levels along a quantity that grows towards coarser levels (distance, or minus the size).
// `beyond(i, margin)`: past boundary i by `margin`; `inside(i, margin)`: before it by `margin`.
template <typename Beyond, typename Inside>
int selectLevel(int levels, int current, float hysteresis, Beyond beyond, Inside inside) {
  if (current < 0) {
    int level = 0;
    while (level < levels - 1 && beyond(level, 0.0f))
      ++level;
    return level;
  }
  int level = std::min(current, levels - 1);
  while (level < levels - 1 && beyond(level, hysteresis))
    ++level;
  while (level > 0 && inside(level - 1, hysteresis))
    --level;
  return level;
}

bool finitePositive(float value) { return std::isfinite(value) && value > 0.0f; }

} // namespace

int selectLevelByDistance(float distance, std::span<const float> switchDistances, int currentLevel, float hysteresis) {
  const int levels = static_cast<int>(switchDistances.size()) + 1;
  return selectLevel(
      levels, currentLevel, hysteresis,
      [&](int i, float h) { return distance >= switchDistances[static_cast<std::size_t>(i)] * (1.0f + h); },
      [&](int i, float h) { return distance < switchDistances[static_cast<std::size_t>(i)] * (1.0f - h); });
}

float projectedSizePixels(float radius, float distance, const ScreenProjection& projection) {
  return radius * projection.viewportHeightPixels / (distance * std::tan(0.5f * projection.verticalFovRadians));
}

int selectLevelByScreenSize(float sizePixels, std::span<const float> switchSizes, int currentLevel, float hysteresis) {
  const int levels = static_cast<int>(switchSizes.size()) + 1;
  return selectLevel(
      levels, currentLevel, hysteresis,
      [&](int i, float h) { return sizePixels < switchSizes[static_cast<std::size_t>(i)] * (1.0f - h); },
      [&](int i, float h) { return sizePixels >= switchSizes[static_cast<std::size_t>(i)] * (1.0f + h); });
}

bool LodSelectionJob::validate() const {
  const std::size_t characters = positions.size();
  if (inout_levels.size() != characters)
    return false;
  if (mode == Mode::ScreenSize && radii.size() != characters)
    return false;
  if (!(hysteresis >= 0.0f && hysteresis < 1.0f))
    return false;
  if (!(projection.verticalFovRadians > 0.0f && projection.verticalFovRadians < 3.14159265f) ||
      !finitePositive(projection.viewportHeightPixels))
    return false;
  for (std::size_t i = 0; i < boundaries.size(); ++i) {
    if (!finitePositive(boundaries[i]))
      return false;
    if (i > 0 && (mode == Mode::Distance ? boundaries[i] <= boundaries[i - 1] : boundaries[i] >= boundaries[i - 1]))
      return false;
  }
  for (std::int32_t level : inout_levels)
    if (level < -1 || level > static_cast<std::int32_t>(boundaries.size()))
      return false;
  return true;
}

bool LodSelectionJob::run() const {
  if (!validate())
    return false;
  for (std::size_t c = 0; c < positions.size(); ++c) {
    const float distance = glm::length(positions[c] - camera);
    std::int32_t& level = inout_levels[c];
    if (mode == Mode::Distance) {
      level = selectLevelByDistance(distance, boundaries, level, hysteresis);
    } else {
      // a character at the camera covers the screen: the finest level
      const float size = distance > 0.0f ? projectedSizePixels(radii[c], distance, projection)
                                         : projection.viewportHeightPixels * 1e6f;
      level = selectLevelByScreenSize(size, boundaries, level, hysteresis);
    }
  }
  return true;
}

} // namespace mlod
