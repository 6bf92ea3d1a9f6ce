#include "core/jpc/jpc_settings.h"

#include <cmath>
#include <sstream>

namespace mlod {

namespace {
std::string number(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

Error validateNonNegative(double value, const std::string& what, const char* unit) {
  if (std::isnan(value))
    return Error(what + " is NaN; it must be a number >= 0 (" + unit + ")");
  if (!std::isfinite(value) || value < 0.0)
    return Error(what + " is " + number(value) + "; it must be finite and >= 0 (" + unit + ")");
  return {};
}
} // namespace

const char* toString(JpcMode mode) {
  return mode == JpcMode::Optimal ? "optimal" : "greedy";
}

std::optional<JpcMode> parseJpcMode(const std::string& text) {
  if (text == "greedy")
    return JpcMode::Greedy;
  if (text == "optimal")
    return JpcMode::Optimal;
  return std::nullopt;
}

double JpcSettings::alphaFor(const std::string& name) const {
  const auto found = joints.find(name);
  return found != joints.end() && found->second.alpha ? *found->second.alpha : alpha;
}

double JpcSettings::thresholdFor(const std::string& name, int level, double levelThreshold) const {
  const auto found = joints.find(name);
  if (found == joints.end() || level < 0)
    return levelThreshold;
  const std::vector<std::optional<double>>& overrides = found->second.thresholds;
  const std::size_t index = static_cast<std::size_t>(level);
  return index < overrides.size() && overrides[index] ? *overrides[index] : levelThreshold;
}

bool JpcSettings::lockedFor(const std::string& name) const {
  const auto found = joints.find(name);
  return found != joints.end() && found->second.locked;
}

double JpcSettings::meshImportanceFor(const std::string& name) const {
  const auto found = joints.find(name);
  return found != joints.end() ? found->second.meshImportance : 1.0;
}

Error validateThreshold(double threshold, const std::string& what) {
  return validateNonNegative(threshold, what, "cm·degrees");
}

Error validateAlpha(double alpha, const std::string& what) {
  return validateNonNegative(alpha, what, "cm");
}

Error validateMeshImportance(double importance, const std::string& what) {
  if (!std::isfinite(importance) || !(importance > 0.0))
    return Error(what + " must be a finite number > 0");
  return {};
}

Error JpcSettings::validate(const Skeleton& skeleton) const {
  if (Error error = validateAlpha(alpha))
    return error;
  if (Error error = validateNonNegative(zeroLength, "the zero-length tolerance", "cm"))
    return error;
  for (const auto& [name, settings] : joints) {
    if (skeleton.find(name) < 0)
      return Error("no joint is named '" + name + "' in the skeleton");
    if (settings.alpha)
      if (Error error = validateAlpha(*settings.alpha, "alpha of joint '" + name + "'"))
        return error;
    if (Error error = validateMeshImportance(settings.meshImportance, "the mesh importance of joint '" + name + "'"))
      return error;
    for (std::size_t level = 0; level < settings.thresholds.size(); ++level)
      if (settings.thresholds[level])
        if (Error error = validateThreshold(*settings.thresholds[level],
                                            "threshold of joint '" + name + "' at level " + std::to_string(level)))
          return error;
  }
  return {};
}

} // namespace mlod
