#pragma once
// How a file becomes an Asset: unit scale and resampling rate.

#include <optional>
#include <span>
#include <string>

namespace mlod {

struct ImportOptions {
  // cm per file unit. 0 = the file's own: glTF x100 (metres by its spec), FBX its
  // UnitScaleFactor, Collada its <unit meter> x100; a file without a unit of its own (BVH,
  // X, OBJ, SMD ..., or an FBX without UnitScaleFactor) gets a guessed one
  // (guessUnitPreset()), 1 when no guess fits.
  double unitScale = 0.0;
  // Resampling rate for formats without a frame time of their own (every format but BVH,
  // which keeps its "Frame Time", and a glTF whose animations state their source's fps in
  // their extras, docs/gltf-extension.md), frames per second.
  double fps = 30.0;
};

// A named unit for formats that carry none (BVH above all).
struct UnitPreset {
  const char* name;       // what users type: "cm", "m", "inch", "cmu" ...
  double cmPerUnit;
  const char* description;
};

std::span<const UnitPreset> unitPresets();

// A human stands about 170 cm; the guess accepts a height within 100-250 cm.
inline constexpr double kHumanHeightCm = 170.0;
inline constexpr double kGuessMinHeightCm = 100.0;
inline constexpr double kGuessMaxHeightCm = 250.0;

// The unit of a file that states none (docs/architecture.md section 3): of the presets, the one
// that puts `heightInFileUnits` (the standing height, core/asset.h standingHeightCm() of the
// asset read at 1 cm per unit) closest to kHumanHeightCm, provided one lands within
// [kGuessMinHeightCm, kGuessMaxHeightCm]; null when none does (not a human figure: keep 1).
const UnitPreset* guessUnitPreset(double heightInFileUnits);

// Parses a unit scale given as a number of cm per unit ("5.6444") or a preset name
// ("cmu"); empty when it is neither, or not a positive finite number.
std::optional<double> parseUnitScale(const std::string& text);

} // namespace mlod
