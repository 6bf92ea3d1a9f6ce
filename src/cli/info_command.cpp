#include "cli/info_command.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <iostream>

namespace mlod::cli {

void InfoCommand::attach(CLI::App& app) {
  CLI::App* command = app.add_subcommand("info", "Describe a file: joints, clips, meshes, unit");
  command->add_option("FILE", file, "character or motion file (any format Assimp reads)")->required();
  command->add_flag("--json", json, "print one JSON document on stdout");
  addImportOptions(*command, import);
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

int InfoCommand::run() const {
  const std::optional<Asset> asset = importForCommand(file, import);
  if (!asset)
    return kExitBadInput;
  if (json) {
    std::cout << describeAssetJson(*asset) << std::endl;
    return kExitOk;
  }
  const Skeleton& skeleton = asset->skeleton;
  std::printf("file:     %s\nformat:   %s\nunit:     %g cm per file unit (%s)\n", asset->sourcePath.c_str(),
              asset->format.c_str(), asset->unitScale, asset->unitSource.c_str());
  const Clip* first = asset->clips.empty() ? nullptr : &asset->clips.front();
  std::printf("skeleton: %d joints (%d leaves", skeleton.jointCount(), skeleton.leafCount());
  if (first)
    std::printf(", %d with rotation channels", first->rotationChannelCount());
  std::printf(")\n");
  printJointTree(skeleton, first);
  std::printf("clips:    %zu\n", asset->clips.size());
  for (const Clip& clip : asset->clips)
    std::printf("  %-24s %7d frames  %8.3f fps  %9.3f s\n", clip.name.c_str(), clip.frameCount, clip.fps,
                clip.durationSeconds());
  std::printf("meshes:   %zu\n", asset->meshes.size());
  for (const SkinnedMesh& mesh : asset->meshes)
    std::printf("  %-24s %7zu vertices  %7zu triangles  %4d bones  %zu parts\n", mesh.name.c_str(),
                mesh.vertexCount(), mesh.triangleCount(), mesh.boneCount(), mesh.parts.size());
  for (const std::string& warning : asset->warnings)
    std::printf("warning:  %s\n", warning.c_str());
  return kExitOk;
}

} // namespace mlod::cli
