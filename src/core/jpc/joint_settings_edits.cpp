#include "core/jpc/joint_settings_edits.h"

#include <cassert>
#include <vector>

namespace mlod {

void tidyJointSettings(JointSettingsMap& joints) {
  for (auto it = joints.begin(); it != joints.end();) {
    auto& t = it->second.thresholds;
    while (!t.empty() && !t.back())
      t.pop_back();
    if (!it->second.alpha && t.empty() && !it->second.locked && it->second.meshImportance == 1.0)
      it = joints.erase(it);
    else
      ++it;
  }
}

Result<JointSettingsMap> withJointAlpha(const JointSettingsMap& joints, std::span<const std::string> names,
                                        std::optional<double> alpha) {
  if (alpha)
    if (Error error = validateAlpha(*alpha))
      return error;
  JointSettingsMap out = joints;
  for (const std::string& name : names)
    out[name].alpha = alpha;
  tidyJointSettings(out);
  return out;
}

Result<JointSettingsMap> withJointThreshold(const JointSettingsMap& joints, std::span<const std::string> names,
                                            int level, std::optional<double> threshold) {
  if (level <= 0)
    return Error("level " + std::to_string(level) + " has no threshold to override (level 0 is the original)");
  if (threshold)
    if (Error error = validateThreshold(*threshold))
      return error;
  JointSettingsMap out = joints;
  for (const std::string& name : names) {
    auto& t = out[name].thresholds;
    if (static_cast<int>(t.size()) <= level)
      t.resize(static_cast<std::size_t>(level) + 1);
    t[static_cast<std::size_t>(level)] = threshold;
  }
  tidyJointSettings(out);
  return out;
}

Result<JointSettingsMap> withJointMeshImportance(const JointSettingsMap& joints, std::span<const std::string> names,
                                                 double importance) {
  if (Error error = validateMeshImportance(importance))
    return error;
  JointSettingsMap out = joints;
  for (const std::string& name : names)
    out[name].meshImportance = importance;
  tidyJointSettings(out);
  return out;
}

JointSettingsMap withJointsLocked(const JointSettingsMap& joints, std::span<const std::string> names, bool locked) {
  JointSettingsMap out = joints;
  for (const std::string& name : names)
    out[name].locked = locked;
  tidyJointSettings(out);
  return out;
}

JointSettingsMap withSettingsOnDescendants(const JointSettingsMap& joints, const Skeleton& skeleton, int joint) {
  assert(joint >= 0 && joint < skeleton.jointCount());
  JointSettingsMap out = joints;
  const auto found = out.find(skeleton.joints[std::size_t(joint)].name);
  const JointSettings source = found != out.end() ? found->second : JointSettings{};
  std::vector<int> stack = skeleton.children(joint);
  while (!stack.empty()) {
    const int child = stack.back();
    stack.pop_back();
    out[skeleton.joints[std::size_t(child)].name] = source;
    for (int grandChild : skeleton.children(child))
      stack.push_back(grandChild);
  }
  tidyJointSettings(out);
  return out;
}

} // namespace mlod
