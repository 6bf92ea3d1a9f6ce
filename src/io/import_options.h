#pragma once
// How a file becomes an Asset: unit scale and resampling rate.

#include <optional>
#include <span>
#include <string>

namespace mlod {

struct ImportOptions {
  // cm per file unit. 0 = the file's own: glTF x100 (metres by its spec), FBX its
  // UnitScaleFactor, Collada its <unit meter> x100, everything else (BVH included) 1.
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

// Parses a unit scale given as a number of cm per unit ("5.6444") or a preset name
// ("cmu"); empty when it is neither, or not a positive finite number.
std::optional<double> parseUnitScale(const std::string& text);

} // namespace mlod
