#include "core/project_package.h"

#include "core/mapping/motion_mapping.h"

#include <algorithm>
#include <filesystem>
#include <string>

namespace mlod {

namespace {
bool hasSkinnedMesh(const Asset& asset) {
  return std::any_of(asset.meshes.begin(), asset.meshes.end(), [](const SkinnedMesh& mesh) { return mesh.skinned(); });
}
} // namespace

Result<std::vector<Clip>> assignedClips(const Project& project, std::span<const Asset* const> imported, int character) {
  if (character < 0 || character >= static_cast<int>(imported.size()) || !imported[std::size_t(character)])
    return Error("the project has no imported asset " + std::to_string(character));
  const Asset& target = *imported[std::size_t(character)];
  std::vector<Clip> out;
  for (const ProjectMapping& mapping : project.mappings) {
    if (mapping.character != character)
      continue;
    const Asset* motion = mapping.motion >= 0 && mapping.motion < static_cast<int>(imported.size())
                              ? imported[std::size_t(mapping.motion)]
                              : nullptr;
    if (!motion) {
      const std::string name = mapping.motion >= 0 && mapping.motion < static_cast<int>(project.assets.size())
                                   ? project.assets[std::size_t(mapping.motion)].path
                                   : "motion " + std::to_string(mapping.motion);
      return Error(name + " (a motion assigned to the character) could not be imported");
    }
    Result<RestPoseDifferences> differences = restPoseDifferences(mapping.mapping, motion->skeleton, target.skeleton);
    if (!differences)
      return Error("mapping of " + mapping.mapping.motionName + ": " + differences.message());
    for (const Clip& clip : motion->clips) {
      Result<Clip> retargeted = retargetClip(*differences, motion->skeleton, clip, target.skeleton);
      if (!retargeted)
        return Error(mapping.mapping.motionName + ": " + retargeted.message());
      out.push_back(std::move(retargeted).value());
    }
  }
  return out;
}

Result<LodPackage> buildLodPackage(const Project& project, std::span<const Asset* const> imported, int asset,
                                   std::span<const int> levels, const LodPackageProgress& progress,
                                   const std::atomic<bool>* cancel) {
  if (Error error = project.validate())
    return error;
  if (asset < 0 || asset >= static_cast<int>(project.assets.size()))
    return Error("the project has no asset " + std::to_string(asset));
  if (imported.size() != project.assets.size())
    return Error("the project's assets were not all imported");
  const Asset* character = imported[std::size_t(asset)];
  if (!character)
    return Error(project.assets[std::size_t(asset)].path + " could not be imported");
  Result<std::vector<Clip>> extra = assignedClips(project, imported, asset);
  if (!extra)
    return extra.error();
  return buildLodPackage(*character, lodSetFor(project, asset), project.jpcSettings(asset, character->unitScale),
                         levels, progress, *extra, cancel);
}

namespace {
std::uint64_t framesOf(const Asset& asset) {
  std::uint64_t frames = 0;
  for (const Clip& clip : asset.clips)
    frames += std::uint64_t(std::max(clip.frameCount, 0));
  return frames;
}
} // namespace

LodPackagePlan packagePlan(const Asset& asset, int levelCount, std::span<const int> levels) {
  LodPackagePlan plan;
  plan.joints = asset.skeleton.jointCount();
  plan.clipFrames = framesOf(asset);
  plan.levels = levels.empty() ? levelCount : static_cast<int>(levels.size());
  plan.withOriginal = levels.empty() || std::find(levels.begin(), levels.end(), 0) != levels.end();
  return plan;
}

LodPackagePlan packagePlan(const Project& project, std::span<const Asset* const> imported, int asset,
                           std::span<const int> levels) {
  const auto importedAt = [&](int i) {
    return i >= 0 && std::size_t(i) < imported.size() ? imported[std::size_t(i)] : nullptr;
  };
  const Asset* character = importedAt(asset);
  const int levelCount = static_cast<int>(lodSetFor(project, asset).levels.size());
  if (!character)
    return packagePlan(Asset{}, levelCount, levels); // no joints: what exporters refuse
  LodPackagePlan plan = packagePlan(*character, levelCount, levels);
  for (const ProjectMapping& mapping : project.mappings)
    if (const Asset* motion = mapping.character == asset ? importedAt(mapping.motion) : nullptr)
      plan.clipFrames += framesOf(*motion);
  return plan;
}

int defaultPackageAsset(const Project& project, std::span<const Asset* const> imported) {
  if (project.assets.empty())
    return -1;
  const auto importedAt = [&](int i) {
    return i >= 0 && std::size_t(i) < imported.size() ? imported[std::size_t(i)] : nullptr;
  };
  for (const ProjectMapping& mapping : project.mappings)
    if (const Asset* a = importedAt(mapping.character); a && (!a->clips.empty() || hasSkinnedMesh(*a)))
      return mapping.character;
  for (int i = 0; i < static_cast<int>(project.assets.size()); ++i)
    if (const Asset* a = importedAt(i); a && hasSkinnedMesh(*a))
      return i;
  return 0;
}

int exportCharacterOf(const Project& project, int asset, int viewedCharacter, std::span<const Asset* const> imported) {
  if (const int owner = lodSetOwner(project, asset, viewedCharacter); owner >= 0)
    return owner;
  return imported.empty() ? -1 : defaultPackageAsset(project, imported);
}

namespace {
// Whether asset `asset` is exported as a character: no mapping plays it on another.
bool isExportCharacter(const Project& project, int asset) { return lodSetOwner(project, asset) == asset; }
} // namespace

std::vector<int> exportCharacters(const Project& project) {
  std::vector<int> out;
  for (int a = 0; a < static_cast<int>(project.assets.size()); ++a)
    if (isExportCharacter(project, a))
      out.push_back(a);
  return out;
}

std::string exportCharacterList(const Project& project) {
  std::string out;
  for (int a : exportCharacters(project))
    out += (out.empty() ? "" : ", ") + std::to_string(a) + " " + assetFileName(project, a);
  return out.empty() ? "none" : out;
}

namespace {
bool isIndex(std::string_view text) {
  return !text.empty() && text.size() <= 9 &&
         std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
}

bool names(const Project& project, int asset, std::string_view name) {
  const std::string& stored = project.assets[std::size_t(asset)].path;
  const std::filesystem::path file = std::filesystem::path(stored).filename();
  return name == stored || name == file.string() || (file.has_extension() && name == file.stem().string());
}
} // namespace

Result<int> exportCharacterNamed(const Project& project, std::string_view name) {
  const std::string characters = "; the project's characters: " + exportCharacterList(project);
  const int count = static_cast<int>(project.assets.size());
  std::vector<int> found;
  if (isIndex(name)) {
    const int index = std::stoi(std::string(name));
    if (index >= count)
      return Error("the project has no asset " + std::string(name) + characters);
    found.push_back(index);
  } else {
    for (int a = 0; a < count; ++a)
      if (names(project, a, name))
        found.push_back(a);
  }
  if (found.empty())
    return Error("the project has no character '" + std::string(name) + "'" + characters);
  std::vector<int> kept; // the characters among them
  for (int a : found)
    if (isExportCharacter(project, a))
      kept.push_back(a);
  if (kept.empty()) {
    const int motion = found.front();
    return Error("'" + std::string(name) + "' is a motion (asset " + std::to_string(motion) + "), exported with " +
                 assetFileName(project, lodSetOwner(project, motion)) + ", the character it is mapped onto" +
                 characters);
  }
  if (kept.size() > 1) {
    std::string which;
    for (int a : kept)
      which += (which.empty() ? "" : ", ") + std::to_string(a) + " " + project.assets[std::size_t(a)].path;
    return Error("'" + std::string(name) + "' names " + std::to_string(kept.size()) + " characters (" + which +
                 "): give its index or path");
  }
  return kept.front();
}

} // namespace mlod
