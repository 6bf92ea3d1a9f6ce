#include "cli/info_command.h"

#include "cli/file_checks.h"
#include "core/project.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <iostream>

namespace mlod::cli {

void InfoCommand::attach(CLI::App& app) {
  CLI::App* command = app.add_subcommand("info", "Describe a file: joints, clips, meshes, unit");
  command->add_option("FILE", file, "character or motion file (any format Assimp reads), or a .mlod project")->required();
  command->add_flag("--json", json, "print one JSON document on stdout");
  addImportOptions(*command, import);
  addProjectOptions(*command, project);
}

namespace {
void printJointTree(const Skeleton& skeleton, const Clip* clip) {
  std::vector<int> depth(skeleton.joints.size(), 0);
  for (std::size_t i = 0; i < skeleton.joints.size(); ++i) {
    const Joint& joint = skeleton.joints[i];
    if (joint.parent >= 0)
      depth[i] = depth[static_cast<std::size_t>(joint.parent)] + 1;
    std::string marks;
    if (clip && !clip->hasRotation[i])
      marks += " (no rotation channel)";
    if (joint.inverseBind)
      marks += " [bound]";
    std::printf("  %*s%s%s\n", depth[i] * 2, "", joint.name.c_str(), marks.c_str());
  }
}
} // namespace

namespace {

// The project's settings, levels and mappings, and every asset imported as the editor would.
int describeProject(const std::string& file, bool json, const ImportArguments& import,
                    const ProjectFileOptions& options) {
  Result<Project> read = loadProjectFile(file, options);
  if (!read) {
    printError(file, read.message());
    return kExitBadInput;
  }
  const Project& project = *read;
  nlohmann::json doc;
  doc["file"] = file;
  doc["version"] = kProjectVersion;
  doc["alpha"] = project.alpha;
  doc["mode"] = toString(project.mode);
  const auto levelsJson = [](const LodSet& lods) {
    nlohmann::json levels = nlohmann::json::array();
    for (const LodLevel& level : lods.levels)
      levels.push_back({{"name", level.name},
                        {"threshold", level.motionThreshold},
                        {"mesh_ratio", level.meshRatio},
                        {"switch_distance_cm", level.switchDistanceCm}});
    return levels;
  };
  doc["levels"] = levelsJson(project.lods); // of every asset that plays with the project's set
  bool allFound = true;
  nlohmann::json assets = nlohmann::json::array();
  for (std::size_t a = 0; a < project.assets.size(); ++a) {
    const ProjectAsset& entry = project.assets[a];
    const std::string path = resolveAssetPath(file, entry.path).string();
    int tuned = 0;
    for (const auto& [name, joint] : entry.joints)
      tuned += joint.alpha || joint.locked || !joint.thresholds.empty() ? 1 : 0;
    // The levels it plays with (lodSetFor()): "own" (a character's own set), "project", or
    // "asset N" (a motion mapped onto character N plays with N's).
    const int owner = lodSetOwner(project, int(a));
    const std::string levelsOf = owner != int(a) ? "asset " + std::to_string(owner)
                                 : entry.lods    ? std::string("own")
                                                 : std::string("project");
    nlohmann::json item = {
        {"path", entry.path},    {"resolved", path},      {"unit_scale", entry.unitScale},
        {"tuned_joints", tuned}, {"levels_of", levelsOf}, {"levels", levelsJson(lodSetFor(project, int(a)))},
        {"asset", nullptr}};
    std::error_code error;
    if (!std::filesystem::exists(path, error)) {
      item["error"] = "missing";
      allFound = false;
    } else {
      ImportArguments arguments = import;
      if (arguments.unitScale.empty() && entry.unitScale > 0.0)
        arguments.unitScale = exactNumber(entry.unitScale);
      const std::optional<Asset> asset = importForCommand(path, arguments);
      if (asset)
        item["asset"] = nlohmann::json::parse(describeAssetJson(*asset));
      else {
        item["error"] = "cannot be imported";
        allFound = false;
      }
    }
    assets.push_back(std::move(item));
  }
  doc["assets"] = assets;
  nlohmann::json mappings = nlohmann::json::array();
  for (const ProjectMapping& mapping : project.mappings)
    mappings.push_back({{"motion", mapping.motion},
                        {"character", mapping.character},
                        {"pairs", mapping.mapping.pairs.size()}});
  doc["mappings"] = mappings;

  if (json) {
    std::cout << jsonText(doc) << std::endl;
    return allFound ? kExitOk : kExitBadInput;
  }
  std::printf("project:  %s (Motion LOD project)\nsettings: mode %s, alpha %g cm\n", file.c_str(), toString(project.mode),
              project.alpha);
  std::printf("levels:   %zu (E in cm·degrees; of every asset without its own)\n", project.lods.levels.size());
  for (std::size_t i = 0; i < project.lods.levels.size(); ++i) {
    const LodLevel& level = project.lods.levels[i];
    if (i == 0)
      std::printf("  %-12s original\n", level.name.c_str());
    else
      std::printf("  %-12s E=%-8g mesh %5.1f%%  from %g m\n", level.name.c_str(), level.motionThreshold,
                  100.0 * level.meshRatio, level.switchDistanceCm / 100.0);
  }
  std::printf("assets:   %zu\n", project.assets.size());
  for (std::size_t a = 0; a < assets.size(); ++a) {
    const nlohmann::json& item = assets[a];
    std::printf("  [%zu] %s", a, item["resolved"].get<std::string>().c_str());
    if (item.contains("error")) {
      std::printf("  %s\n", item["error"].get<std::string>() == "missing" ? "MISSING (relink it in the editor)"
                                                                           : "CANNOT BE IMPORTED");
      continue;
    }
    const nlohmann::json& asset = item["asset"];
    std::printf("\n       %g cm per file unit, %zu joints, %d tuned; clips:", project.assets[a].unitScale > 0.0
                                                                                    ? project.assets[a].unitScale
                                                                                    : asset.value("unit_scale", 0.0),
                asset.contains("joints") ? asset["joints"].size() : std::size_t(0), item["tuned_joints"].get<int>());
    if (asset.contains("clips"))
      for (const nlohmann::json& clip : asset["clips"])
        std::printf(" %s (%d frames)", clip.value("name", std::string()).c_str(), clip.value("frames", 0));
    std::printf("; meshes: %zu\n", asset.contains("meshes") ? asset["meshes"].size() : std::size_t(0));
    if (const int owner = lodSetOwner(project, int(a)); owner != int(a)) { // a mapped motion
      std::printf("       plays with asset %d's LOD set (its character)\n", owner);
    } else if (const std::optional<LodSet>& own = project.assets[a].lods) { // version 4: a character's own levels
      std::printf("       its own LOD set, %zu levels:", own->levels.size());
      for (const LodLevel& level : own->levels)
        std::printf(" %s (E=%g, mesh %.1f%%, from %g m)", level.name.c_str(), level.motionThreshold,
                    100.0 * level.meshRatio, level.switchDistanceCm / 100.0);
      std::printf("\n");
    }
  }
  std::printf("mappings: %zu\n", project.mappings.size());
  for (const ProjectMapping& mapping : project.mappings)
    std::printf("  asset %d drives asset %d (%zu joint pairs)\n", mapping.motion, mapping.character,
                mapping.mapping.pairs.size());
  return allFound ? kExitOk : kExitBadInput;
}
} // namespace

int InfoCommand::run() const {
  if (isProjectFile(file))
    return describeProject(file, json, import, project);
  const std::optional<Asset> asset = importForCommand(file, import);
  if (!asset)
    return kExitBadInput;
  if (json) {
    warnIfNotUtf8(file);
    std::cout << describeAssetJson(*asset) << std::endl;
    return kExitOk;
  }
  const Skeleton& skeleton = asset->skeleton;
  std::printf("file:     %s\nformat:   %s\nunit:     %g cm per file unit (%s)\nheight:   %.1f cm\n",
              asset->sourcePath.c_str(), asset->format.c_str(), asset->unitScale, asset->unitSource.c_str(),
              standingHeightCm(*asset));
  const Clip* first = asset->clips.empty() ? nullptr : &asset->clips.front();
  std::printf("skeleton: %d joints (%d leaves", skeleton.jointCount(), skeleton.leafCount());
  if (first)
    std::printf(", %d with rotation channels", first->rotationChannelCount());
  std::printf(")\n");
  printJointTree(skeleton, first);
  std::printf("clips:    %zu\n", asset->clips.size());
  for (std::size_t c = 0; c < asset->clips.size(); ++c) {
    const Clip& clip = asset->clips[c];
    std::printf("  %-24s %7d frames  %8.3f fps  %9.3f s", clip.name.c_str(), clip.frameCount, clip.fps,
                clip.durationSeconds());
    if (c < asset->clusters.size()) // the clusters a glTF's MLOD_joint_clusters carries
      std::printf("  %6d clusters", asset->clusters[c].clusterCount());
    std::printf("\n");
  }
  std::printf("meshes:   %zu\n", asset->meshes.size());
  for (const SkinnedMesh& mesh : asset->meshes)
    std::printf("  %-24s %7zu vertices  %7zu triangles  %4d bones  %zu parts\n", mesh.name.c_str(),
                mesh.vertexCount(), mesh.triangleCount(), mesh.boneCount(), mesh.parts.size());
  for (const std::string& warning : asset->warnings)
    std::printf("warning:  %s\n", warning.c_str());
  return kExitOk;
}

} // namespace mlod::cli
