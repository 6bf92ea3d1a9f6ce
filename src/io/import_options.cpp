#include "io/import_options.h"

#include <array>
#include <cmath>
#include <cstdlib>

namespace mlod {

namespace {
// note: CMU's mocap skeletons are in units of 1/0.45 inch (their documentation), so
// 2.54 / 0.45 = 5.6444 cm per unit.
constexpr std::array kPresets{
    UnitPreset{"cm", 1.0, "centimetres (FBX default)"},
    UnitPreset{"m", 100.0, "metres (glTF)"},
    UnitPreset{"mm", 0.1, "millimetres"},
    UnitPreset{"inch", 2.54, "inches"},
    UnitPreset{"cmu", 2.54 / 0.45, "CMU motion-capture database (1/0.45 inch)"},
};
} // namespace

std::span<const UnitPreset> unitPresets() { return kPresets; }

const UnitPreset* guessUnitPreset(double heightInFileUnits) {
  if (!std::isfinite(heightInFileUnits) || heightInFileUnits <= 0.0)
    return nullptr;
  const UnitPreset* best = nullptr;
  for (const UnitPreset& preset : kPresets) {
    const double height = heightInFileUnits * preset.cmPerUnit;
    if (height < kGuessMinHeightCm || height > kGuessMaxHeightCm)
      continue;
    if (!best || std::abs(height - kHumanHeightCm) < std::abs(heightInFileUnits * best->cmPerUnit - kHumanHeightCm))
      best = &preset;
  }
  return best;
}

std::optional<double> parseUnitScale(const std::string& text) {
  for (const UnitPreset& preset : kPresets)
    if (text == preset.name)
      return preset.cmPerUnit;
  if (text.empty())
    return std::nullopt;
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || !std::isfinite(value) || value <= 0.0)
    return std::nullopt;
  return value;
}

} // namespace mlod
