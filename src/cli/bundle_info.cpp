#include "cli/bundle_info.h"

#include "cli/cli_common.h"
#include "runtime/bundle.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>

namespace mlod::cli {

bool isBundleFile(const std::string& file) {
  return file.size() >= 6 && file.compare(file.size() - 6, 6, ".mlodb") == 0;
}

int describeBundle(const std::string& file, bool json) {
  const auto start = std::chrono::steady_clock::now();
  std::string error;
  std::optional<Bundle> bundle = readBundleFile(file, &error);
  if (!bundle) {
    printError(file, error);
    return kExitBadInput;
  }
  // what an engine builds from it: every clip and mesh must build
  std::vector<BundleLevelRuntime> runtime;
  for (const BundleLevel& level : bundle->levels) {
    std::optional<BundleLevelRuntime> built = buildBundleLevel(level, &error);
    if (!built) {
      printError(file, error);
      return kExitBadInput;
    }
    runtime.push_back(std::move(*built));
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::error_code sizeError;
  const std::uintmax_t bytes = std::filesystem::file_size(file, sizeError);
  nlohmann::json levels = nlohmann::json::array();
  for (std::size_t l = 0; l < bundle->levels.size(); ++l) {
    const BundleLevel& level = bundle->levels[l];
    nlohmann::json clips = nlohmann::json::array();
    for (std::size_t c = 0; c < level.clips.size(); ++c)
      clips.push_back({{"name", level.clips[c].name},
                       {"frames", level.clips[c].frameCount},
                       {"fps", level.clips[c].fps},
                       {"looping", level.clips[c].looping},
                       {"clusters", level.clips[c].clusters.size()},
                       {"bytes", runtime[l].clips[c].byteSize()}});
    nlohmann::json mesh = nullptr;
    if (level.mesh)
      mesh = {{"vertices", level.mesh->positions.size()}, {"triangles", level.mesh->indices.size() / 3}};
    levels.push_back({{"index", level.index},
                      {"name", level.name},
                      {"threshold", level.motionThreshold},
                      {"mesh_ratio", level.meshRatio},
                      {"switch_distance_cm", level.switchDistanceCm},
                      {"joints", level.jointCount()},
                      {"clips", clips},
                      {"mesh", mesh}});
  }
  if (json) {
    const nlohmann::json doc = {{"file", file},
                                {"format", "motionlod-bundle"},
                                {"version", kBundleVersion},
                                {"bytes", bytes},
                                {"name", bundle->name},
                                {"source", bundle->source},
                                {"joints", bundle->jointNames.size()},
                                {"bounding_radius_cm", bundle->boundingRadiusCm},
                                {"levels", levels},
                                {"seconds", seconds}};
    std::cout << doc.dump(2) << std::endl;
    return kExitOk;
  }
  std::printf("file:     %s\nformat:   Motion LOD runtime bundle, version %u, %ju bytes\n", file.c_str(),
              kBundleVersion, bytes);
  std::printf("name:     %s (from %s)\nskeleton: %zu joints; bounding radius %.1f cm\n", bundle->name.c_str(),
              bundle->source.c_str(), bundle->jointNames.size(), bundle->boundingRadiusCm);
  std::printf("levels:   %zu\n", bundle->levels.size());
  for (std::size_t l = 0; l < bundle->levels.size(); ++l) {
    const BundleLevel& level = bundle->levels[l];
    std::printf("  [%d] %-8s E=%-6g from %8.2f m  %3d joints", level.index, level.name.c_str(), level.motionThreshold,
                level.switchDistanceCm / 100.0, level.jointCount());
    if (level.mesh)
      std::printf("  mesh %zu vertices, %zu triangles", level.mesh->positions.size(), level.mesh->indices.size() / 3);
    std::printf("\n");
    for (std::size_t c = 0; c < level.clips.size(); ++c)
      std::printf("       clip %-20s %6d frames %8.3f fps  %5zu clusters  %8zu bytes at run time\n",
                  level.clips[c].name.c_str(), level.clips[c].frameCount, level.clips[c].fps,
                  level.clips[c].clusters.size(), runtime[l].clips[c].byteSize());
  }
  std::printf("read and built in %.3f s\n", seconds);
  return kExitOk;
}

} // namespace mlod::cli
