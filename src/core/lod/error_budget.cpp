#include "core/lod/error_budget.h"

#include "runtime/lod_selection.h"

#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>

namespace mlod {

double LodProjection::focalPixels() const {
  return viewportHeightPixels / (2.0 * std::tan(verticalFovDegrees * std::numbers::pi / 360.0));
}

Error LodProjection::validate() const {
  if (!std::isfinite(verticalFovDegrees) || !(verticalFovDegrees > 0.0 && verticalFovDegrees < 180.0))
    return Error("projection: the vertical field of view must be in (0, 180) degrees");
  if (!std::isfinite(viewportHeightPixels) || !(viewportHeightPixels > 0.0))
    return Error("projection: the viewport height must be > 0 pixels");
  return {};
}

double deviationPixels(double deviationCm, double distanceCm, double radiusCm, const LodProjection& projection) {
  assert(deviationCm >= 0.0 && radiusCm >= 0.0);
  if (deviationCm == 0.0)
    return 0.0; // nothing moves: no pixel changes, wherever the camera is
  const double reach = radiusCm + deviationCm; // every moved point lies within it
  const double depth = distanceCm - reach;
  if (!(depth > 0.0))
    return std::numeric_limits<double>::infinity();
  const double sine = reach / distanceCm;
  return projection.focalPixels() * deviationCm / (depth * std::sqrt(1.0 - sine * sine));
}

double deviationForPixels(double pixels, double distanceCm, double radiusCm, const LodProjection& projection) {
  assert(pixels > 0.0);
  // pixels(delta) rises with delta from 0: bisection
  double lo = 0.0, hi = std::max(0.0, distanceCm - radiusCm);
  if (hi == 0.0)
    return 0.0;
  for (int i = 0; i < 200 && hi - lo > 1e-12 * std::max(1.0, hi); ++i) {
    const double mid = 0.5 * (lo + hi);
    if (deviationPixels(mid, distanceCm, radiusCm, projection) <= pixels)
      lo = mid;
    else
      hi = mid;
  }
  return lo;
}

double distanceForPixels(double deviationCm, double pixels, double radiusCm, const LodProjection& projection) {
  assert(pixels > 0.0 && deviationCm >= 0.0);
  if (deviationCm == 0.0)
    return radiusCm;
  // an infinite (or NaN) size has no distance: the doubling below would never end
  if (!std::isfinite(deviationCm) || !std::isfinite(radiusCm))
    return std::numeric_limits<double>::infinity();
  // pixels(d) falls as d grows: grow an upper end, then bisect
  double lo = radiusCm + deviationCm, hi = 2.0 * lo + 1.0;
  while (deviationPixels(deviationCm, hi, radiusCm, projection) > pixels && std::isfinite(hi))
    hi *= 2.0;
  if (!std::isfinite(hi))
    return hi;
  for (int i = 0; i < 200 && hi - lo > 1e-9 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (deviationPixels(deviationCm, mid, radiusCm, projection) <= pixels)
      hi = mid;
    else
      lo = mid;
  }
  return hi;
}

double screenSizePixels(double radiusCm, double distanceCm, const LodProjection& projection) {
  ScreenProjection screen;
  screen.verticalFovRadians = static_cast<float>(projection.verticalFovDegrees * std::numbers::pi / 180.0);
  screen.viewportHeightPixels = static_cast<float>(projection.viewportHeightPixels);
  return projectedSizePixels(static_cast<float>(radiusCm), static_cast<float>(distanceCm), screen);
}

double distanceForScreenSize(double radiusCm, double sizePixels, const LodProjection& projection) {
  assert(sizePixels > 0.0);
  // the runtime's size: 2 R / (2 d tan(fov / 2)) x height = 2 R f / d
  return 2.0 * radiusCm * projection.focalPixels() / sizePixels;
}

} // namespace mlod
