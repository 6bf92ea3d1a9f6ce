#include "core/lod/lod_levels.h"

#include "core/jpc/jpc_settings.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

namespace mlod {

namespace {
std::vector<int> identity(std::size_t count) {
  std::vector<int> order(count);
  std::iota(order.begin(), order.end(), 0);
  return order;
}

LodSetEdit inPlace(const LodSet& lods) {
  return {lods, identity(lods.levels.size())};
}

int count(const LodSet& lods) {
  return static_cast<int>(lods.levels.size());
}

Error outOfRange(const LodSet& lods, int level) {
  if (level < 0 || level >= count(lods))
    return Error("no level " + std::to_string(level));
  return {};
}

// The simplified levels only: the original keeps its threshold, ratio, distance and place.
Error notOriginal(const LodSet& lods, int level, const std::string& what) {
  if (Error error = outOfRange(lods, level))
    return error;
  if (level == 0)
    return Error("level 0 is the original: " + what);
  return {};
}

std::string number(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

std::string_view trimmed(std::string_view text) {
  const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v'; };
  while (!text.empty() && blank(text.front()))
    text.remove_prefix(1);
  while (!text.empty() && blank(text.back()))
    text.remove_suffix(1);
  return text;
}
} // namespace

std::string nextLodLevelName(const LodSet& lods) {
  const auto taken = [&](const std::string& name) {
    return std::any_of(lods.levels.begin(), lods.levels.end(), [&](const LodLevel& l) { return l.name == name; });
  };
  int n = count(lods);
  while (taken("LOD" + std::to_string(n)))
    ++n;
  return "LOD" + std::to_string(n);
}

double nextLodLevelThreshold(const LodSet& lods) {
  const double last = lods.levels.empty() ? 0.0 : lods.levels.back().motionThreshold;
  return last <= 0.0 ? 5.0 : last * 2.0;
}

std::optional<double> switchDistancePixelBudget(const LodSet& lods) {
  for (const LodLevel& level : lods.levels)
    if (level.switchDistanceCm > 0.0)
      return level.pixelError > 0.0 ? level.pixelError : 1.0;
  return std::nullopt;
}

Result<LodSetEdit> addLodLevel(const LodSet& lods, double threshold) {
  assert(!lods.levels.empty());
  if (Error error = validateThreshold(threshold))
    return error;
  LodSetEdit out = inPlace(lods);
  LodLevel level;
  level.name = nextLodLevelName(lods);
  level.motionThreshold = threshold;
  level.meshRatio = lods.levels.back().meshRatio;
  level.switchDistanceCm = lods.levels.back().switchDistanceCm;
  out.lods.levels.push_back(std::move(level));
  out.order.push_back(-1);
  return out;
}

Result<LodSetEdit> removeLodLevel(const LodSet& lods, int level) {
  if (Error error = notOriginal(lods, level, "it is never removed"))
    return error;
  LodSetEdit out = inPlace(lods);
  out.lods.levels.erase(out.lods.levels.begin() + level);
  out.order.erase(out.order.begin() + level);
  return out;
}

Result<LodSetEdit> moveLodLevel(const LodSet& lods, int from, int to) {
  if (Error error = notOriginal(lods, from, "it stays first"))
    return error;
  if (Error error = notOriginal(lods, to, "it stays first"))
    return error;
  if (from == to)
    return Error("level " + std::to_string(from) + " is already at position " + std::to_string(to));
  LodSetEdit out = inPlace(lods);
  const int moved = out.order[std::size_t(from)];
  out.order.erase(out.order.begin() + from);
  out.order.insert(out.order.begin() + to, moved);
  for (std::size_t i = 0; i < out.order.size(); ++i) {
    out.lods.levels[i] = lods.levels[std::size_t(out.order[i])];
    out.lods.levels[i].switchDistanceCm = lods.levels[i].switchDistanceCm; // distances stay with the positions
  }
  return out;
}

Result<LodSetEdit> setLodLevelThreshold(const LodSet& lods, int level, double threshold) {
  if (Error error = notOriginal(lods, level, "its threshold is 0"))
    return error;
  if (Error error = validateThreshold(threshold, "level " + std::to_string(level) + " threshold"))
    return error;
  LodSetEdit out = inPlace(lods);
  out.lods.levels[std::size_t(level)].motionThreshold = threshold;
  return out;
}

Result<LodSetEdit> renameLodLevel(const LodSet& lods, int level, std::string_view name) {
  if (Error error = outOfRange(lods, level))
    return error;
  const std::string text(trimmed(name));
  if (text.empty())
    return Error("a level needs a name");
  if (text.size() > kMaxLevelNameBytes)
    return Error("a level name has at most " + std::to_string(kMaxLevelNameBytes) + " bytes; this one has " +
                 std::to_string(text.size()));
  for (int i = 0; i < count(lods); ++i)
    if (i != level && lods.levels[std::size_t(i)].name == text)
      return Error("level " + std::to_string(i) + " is already named '" + text + "'");
  LodSetEdit out = inPlace(lods);
  out.lods.levels[std::size_t(level)].name = text;
  return out;
}

Result<LodSetEdit> setLodLevelMeshRatio(const LodSet& lods, int level, double ratio) {
  if (Error error = notOriginal(lods, level, "its mesh ratio is 1"))
    return error;
  if (!(ratio > 0.0 && ratio <= 1.0))
    return Error("a mesh ratio is in (0, 1]");
  LodSetEdit out = inPlace(lods);
  out.lods.levels[std::size_t(level)].meshRatio = ratio;
  return out;
}

Result<LodSetEdit> setLodLevelSwitchDistance(const LodSet& lods, int level, double cm) {
  if (Error error = notOriginal(lods, level, "it is used from distance 0"))
    return error;
  const double low = lods.levels[std::size_t(level - 1)].switchDistanceCm;
  if (!std::isfinite(cm) || cm < low)
    return Error("level " + std::to_string(level) +
                 "'s switch distance must be finite and at least the previous level's (" + number(low) + " cm)");
  LodSetEdit out = inPlace(lods);
  for (int i = level; i < count(lods); ++i) // later levels nearer than this one move out with it
    if (i == level || out.lods.levels[std::size_t(i)].switchDistanceCm < cm)
      out.lods.levels[std::size_t(i)].switchDistanceCm = cm;
  return out;
}

LodSetEdit replaceLodLevels(const LodSet& before, LodSet generated) {
  std::vector<int> order = identity(std::min(before.levels.size(), generated.levels.size()));
  order.insert(order.end(), generated.levels.size() - order.size(), -1);
  return {std::move(generated), std::move(order)};
}

std::vector<LodOverrideAbove> overridesAboveLevels(const JpcSettings& settings, const LodSet& lods) {
  std::vector<LodOverrideAbove> out;
  for (std::size_t level = 0; level < lods.levels.size(); ++level)
    for (const auto& [joint, own] : settings.joints) { // a std::map: by name
      if (level >= own.thresholds.size() || !own.thresholds[level])
        continue;
      const double threshold = lods.levels[level].motionThreshold;
      if (*own.thresholds[level] > threshold)
        out.push_back({joint, static_cast<int>(level), *own.thresholds[level], threshold});
    }
  return out;
}

} // namespace mlod
