#include "core/project_mappings.h"

namespace mlod {

namespace {
const Asset* importedAt(std::span<const Asset* const> imported, int index) {
  return index >= 0 && index < static_cast<int>(imported.size()) ? imported[std::size_t(index)] : nullptr;
}

Error noMapping(const Project& project, int mapping) {
  if (mapping < 0 || mapping >= static_cast<int>(project.mappings.size()))
    return Error("the project has no mapping " + std::to_string(mapping));
  return {};
}

// The motion and character skeletons of mapping `mapping`; null when either is missing.
std::pair<const Asset*, const Asset*> assetsOf(const Project& project, std::span<const Asset* const> imported,
                                               int mapping) {
  const ProjectMapping& entry = project.mappings[std::size_t(mapping)];
  return {importedAt(imported, entry.motion), importedAt(imported, entry.character)};
}
} // namespace

Result<std::vector<ProjectMapping>> withMotionAssigned(const Project& project, std::span<const Asset* const> imported,
                                                       int motion, int character, const std::string& motionName,
                                                       const std::string& characterName) {
  const int count = static_cast<int>(project.assets.size());
  if (motion < 0 || motion >= count || character < 0 || character >= count || motion == character)
    return Error("choose a motion and a different character");
  const Asset* source = importedAt(imported, motion);
  const Asset* target = importedAt(imported, character);
  if (!source || !target)
    return Error("an asset is missing; relink it first");
  if (source->clips.empty())
    return Error(motionName + " has no clip to play");
  ProjectMapping mapping;
  mapping.motion = motion;
  mapping.character = character;
  mapping.mapping = MotionMapping::automatic(source->skeleton, target->skeleton);
  mapping.mapping.motionName = motionName;
  mapping.mapping.characterName = characterName;
  if (mapping.mapping.pairs.empty())
    return Error("no joint of " + motionName + " matches one of " + characterName);
  std::vector<ProjectMapping> out;
  for (const ProjectMapping& existing : project.mappings)
    if (existing.motion != motion || existing.character != character)
      out.push_back(existing);
  out.push_back(std::move(mapping));
  return out;
}

Result<std::vector<ProjectMapping>> withoutMapping(const Project& project, int mapping) {
  if (Error error = noMapping(project, mapping))
    return error;
  std::vector<ProjectMapping> out = project.mappings;
  out.erase(out.begin() + mapping);
  return out;
}

Result<std::vector<ProjectMapping>> withMappingPair(const Project& project, std::span<const Asset* const> imported,
                                                    int mapping, const std::string& characterJoint,
                                                    const std::string& motionJoint) {
  if (Error error = noMapping(project, mapping))
    return error;
  const auto [motion, character] = assetsOf(project, imported, mapping);
  if (!motion || !character)
    return Error("an asset is missing; relink it first");
  if (character->skeleton.find(characterJoint) < 0)
    return Error("the character has no joint '" + characterJoint + "'");
  if (!motionJoint.empty() && motion->skeleton.find(motionJoint) < 0)
    return Error("the motion has no joint '" + motionJoint + "'");
  std::vector<ProjectMapping> out = project.mappings;
  MotionMapping& table = out[std::size_t(mapping)].mapping;
  if (motionJoint.empty())
    table.clear(characterJoint);
  else
    table.set(characterJoint, motionJoint);
  return out;
}

Result<std::vector<ProjectMapping>> withAutomaticMapping(const Project& project, std::span<const Asset* const> imported,
                                                         int mapping) {
  if (Error error = noMapping(project, mapping))
    return error;
  const auto [motion, character] = assetsOf(project, imported, mapping);
  if (!motion || !character)
    return Error("an asset is missing; relink it first");
  std::vector<ProjectMapping> out = project.mappings;
  MotionMapping automatic = MotionMapping::automatic(motion->skeleton, character->skeleton);
  automatic.motionName = out[std::size_t(mapping)].mapping.motionName;
  automatic.characterName = out[std::size_t(mapping)].mapping.characterName;
  out[std::size_t(mapping)].mapping = std::move(automatic);
  return out;
}

} // namespace mlod
