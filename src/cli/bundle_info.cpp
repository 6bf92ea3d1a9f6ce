#include "cli/bundle_info.h"

#include "cli/cli_common.h"
#include "runtime/bundle.h"
#include "runtime/input_file.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <span>

namespace mlod::cli {

bool isBundleFile(const std::string& file) {
  return file.size() >= 6 && file.compare(file.size() - 6, 6, ".mlodb") == 0;
}

namespace {

// The manifest beside a bundle (FILE.mlodb.json) carries the bundle's size and CRC-32: an
// export killed between renaming the bundle and its manifest leaves a manifest of another
// bundle, which is said here (the bundle itself is whole: it has its own CRCs).
void checkManifest(const std::string& file, std::span<const std::uint8_t> bytes) {
  const std::string manifest = file + ".json";
  std::error_code error;
  if (!std::filesystem::exists(manifest, error))
    return;
  std::string reason;
  const std::optional<std::string> text = readInputFile(manifest, std::uint64_t(64) << 20, &reason);
  const nlohmann::json doc = text ? nlohmann::json::parse(*text, nullptr, false) : nlohmann::json();
  if (!doc.is_object() || !doc.contains("bytes") || !doc.contains("crc32")) {
    std::cerr << "warning: " << manifest << ": not a bundle manifest" << (text ? "" : " (" + reason + ")") << std::endl;
    return;
  }
  char crc[16];
  std::snprintf(crc, sizeof crc, "%08x", crc32(bytes));
  if (doc["bytes"] != bytes.size() || doc["crc32"] != crc)
    std::cerr << "warning: " << manifest << ": it does not belong to " << file << " (its bytes and CRC-32 are "
              << doc["bytes"].dump() << " and " << doc["crc32"].dump() << ", the bundle's " << bytes.size() << " and "
              << crc << "): an export stopped between the two? The bundle itself is whole." << std::endl;
}

} // namespace

int describeBundle(const std::string& file, bool json) {
  const auto start = std::chrono::steady_clock::now();
  std::string error;
  const std::optional<std::string> content = readInputFile(file, kMaxBundleFileBytes, &error);
  const auto data = content ? std::span(reinterpret_cast<const std::uint8_t*>(content->data()), content->size())
                            : std::span<const std::uint8_t>();
  std::optional<Bundle> bundle = content ? readBundle(data, &error) : std::nullopt;
  if (!bundle) {
    printError(file, error);
    return kExitBadInput;
  }
  checkManifest(file, data);
  // what an engine builds from it: the clips are read as played (readBundle() checked
  // them); every mesh must build
  for (const BundleLevel& level : bundle->levels)
    if (level.mesh && !level.mesh->build(level.jointCount(), &error)) {
      printError(file, "level '" + level.name + "' mesh: " + error);
      return kExitBadInput;
    }
  const double seconds = secondsSince(start);
  std::error_code sizeError;
  const std::uintmax_t bytes = std::filesystem::file_size(file, sizeError);
  nlohmann::json levels = nlohmann::json::array();
  for (std::size_t l = 0; l < bundle->levels.size(); ++l) {
    const BundleLevel& level = bundle->levels[l];
    nlohmann::json clips = nlohmann::json::array();
    for (const BundleClip& bundleClip : level.clips) {
      const LodClip& clip = bundleClip.clip;
      clips.push_back({{"name", bundleClip.name},
                       {"frames", clip.frameCount()},
                       {"fps", clip.fps()},
                       {"looping", clip.looping()},
                       {"clusters", clip.clusterCount()},
                       {"blend_frames", clip.blendFrames()},
                       {"bytes", clip.byteSize()},
                       {"bytes_in_file", bundleClipBytes(bundleClip)},
                       {"bytes_per_second", clip.bytesPerSecond()},
                       {"precision_cm", clip.precisionCm()},
                       {"encoded_error_cm", clip.encodedErrorCm()}});
    }
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
    std::cout << jsonText(doc) << std::endl;
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
    for (const BundleClip& bundleClip : level.clips) {
      const LodClip& clip = bundleClip.clip;
      std::printf("       clip %-20s %6d frames %8.3f fps  %5d clusters  %8zu bytes at run time, %zu in the file "
                  "(%.0f bytes/s, blend %d frames, error bound %.4g cm, precision %.4g)\n",
                  bundleClip.name.c_str(), clip.frameCount(), clip.fps(), clip.clusterCount(), clip.byteSize(),
                  bundleClipBytes(bundleClip), clip.bytesPerSecond(), clip.blendFrames(), clip.encodedErrorCm(),
                  clip.precisionCm());
    }
  }
  std::printf("read and built in %.3f s\n", seconds);
  return kExitOk;
}

} // namespace mlod::cli
