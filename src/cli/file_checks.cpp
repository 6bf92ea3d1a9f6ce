#include "cli/file_checks.h"

#include "core/project.h"

#include <filesystem>
#include <sys/stat.h>

namespace mlod::cli {

namespace fs = std::filesystem;

std::optional<FileIdentity> fileIdentity(const std::string& path) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0)
    return std::nullopt;
  return FileIdentity{static_cast<std::uint64_t>(info.st_dev), static_cast<std::uint64_t>(info.st_ino)};
}

std::vector<std::string> exportOutputFiles(const std::string& plugin, const std::string& output,
                                           const QVariantMap& options) {
  std::vector<std::string> files{output};
  // plugins/bundle/bundle_plugin.cpp writes FILE.mlodb.json beside the bundle
  if (plugin == "bundle" && options.value("manifest", true).toBool())
    files.push_back(output + ".json");
  // plugins/gltf/gltf_exporter.cpp with split_levels writes OUT_LOD<n>.<suffix> per level
  // instead: every name a project's levels can give (kMaxProjectLevels)
  if (plugin == "gltf" && options.value("split_levels", false).toBool()) {
    const fs::path path(output);
    const std::string format = options.value("format", "auto").toString().toStdString();
    const std::string suffix =
        path.has_extension() ? path.extension().string().substr(1) : (format == "gltf" ? "gltf" : "glb");
    const std::string stem = path.has_extension() ? (path.parent_path() / path.stem()).string() : output;
    files.clear();
    for (int level = 0; level < kMaxProjectLevels; ++level)
      files.push_back(stem + "_LOD" + std::to_string(level) + "." + suffix);
  }
  return files;
}

std::vector<std::string> exportInputFiles(const std::string& input) {
  std::vector<std::string> files{input};
  if (!isProjectFile(input))
    return files;
  // every asset, inside the folder or not: listing one the export will refuse only makes the
  // output check stricter
  const Result<Project> project = loadProjectFile(input, {.allowOutsideAssets = true});
  if (project)
    for (const ProjectAsset& asset : project->assets)
      files.push_back(resolveAssetPath(input, asset.path).string());
  return files;
}

std::string outputProblem(const std::string& output, std::span<const std::string> inputs) {
  struct stat info {};
  if (::stat(output.c_str(), &info) != 0)
    return {}; // nothing there yet (a missing folder is the export's to report)
  if (S_ISDIR(info.st_mode))
    return {}; // nothing is lost: no file can replace a folder (the export says "it is a folder")
  if (!S_ISREG(info.st_mode))
    return std::string("the output exists and is not a regular file (") +
           (S_ISFIFO(info.st_mode)                           ? "a FIFO"
            : S_ISCHR(info.st_mode) || S_ISBLK(info.st_mode) ? "a device"
            : S_ISSOCK(info.st_mode)                         ? "a socket"
                                                             : "not a plain file") +
           "); it is never replaced";
  const FileIdentity identity{static_cast<std::uint64_t>(info.st_dev), static_cast<std::uint64_t>(info.st_ino)};
  for (const std::string& input : inputs)
    if (fileIdentity(input) == identity)
      return "the output is the same file as the input " + input + "; it would be overwritten";
  return {};
}

std::string normalOutputPath(const std::string& path) {
  std::error_code error;
  const fs::path absolute = fs::absolute(path, error);
  const fs::path resolved = fs::weakly_canonical(absolute, error);
  return (error ? absolute.lexically_normal() : resolved).string();
}

bool isInsideFolder(const std::string& path, const std::string& folder) {
  const fs::path relative = fs::path(path).lexically_relative(folder);
  return !relative.empty() && *relative.begin() != "..";
}

} // namespace mlod::cli
