#pragma once
// One error budget (docs/architecture.md section 5): a level's deviation in cm, seen from a camera,
// in pixels; and back, the camera distance from which a deviation stays under N pixels
// (the deviation-to-screen-size relation of Simplygon's LOD switching).
//
// Camera: a pinhole of vertical field of view `fov` over `height` pixels, focal length
// f = height / (2 tan(fov / 2)) pixels, aimed at the centre of the character's bounding
// sphere (radius R cm) from distance d cm. A displacement of length delta at depth z,
// seen at angle phi off the axis, spans at most f delta / (z cos phi) pixels (the
// projection's derivative, x = f X / Z). Every point of the character, moved by up to
// delta, lies within R + delta of the centre: z >= d - R - delta and
// sin phi <= (R + delta) / d. So
//     pixels(delta, d) = f delta / ((d - R - delta) sqrt(1 - ((R + delta) / d)^2))
// is a bound for every point and every direction of the displacement, exact in the worst
// case, and it falls as d grows. Screen size is the runtime's: the sphere's diameter over
// the visible height at distance d (runtime/lod_selection.h).
//
// Units: cm, pixels, degrees for the field of view.

#include "core/error.h"

namespace mlod {

struct LodProjection {
  double verticalFovDegrees = 60.0; // (0, 180)
  double viewportHeightPixels = 1080.0;

  double focalPixels() const; // f
  // Rules: field of view finite in (0, 180) degrees; height finite and > 0.
  Error validate() const;
  friend bool operator==(const LodProjection&, const LodProjection&) = default;
};

// The most pixels a deviation of `deviationCm` (>= 0) can span on screen, the character's
// bounding sphere (`radiusCm`, >= 0) `distanceCm` from the camera: 0 for a deviation of 0,
// else infinity when the camera is inside the sphere grown by the deviation.
double deviationPixels(double deviationCm, double distanceCm, double radiusCm, const LodProjection& projection);

// The largest deviation (cm) that spans at most `pixels` (> 0) at `distanceCm`.
double deviationForPixels(double pixels, double distanceCm, double radiusCm, const LodProjection& projection);

// The smallest distance (cm) from which `deviationCm` spans at most `pixels` (> 0); the
// sphere's radius for a deviation of 0.
double distanceForPixels(double deviationCm, double pixels, double radiusCm, const LodProjection& projection);

// Projected height (pixels) of the bounding sphere at `distanceCm` (> 0).
double screenSizePixels(double radiusCm, double distanceCm, const LodProjection& projection);
// The distance at which the sphere's projected height is `sizePixels` (> 0).
double distanceForScreenSize(double radiusCm, double sizePixels, const LodProjection& projection);

} // namespace mlod
