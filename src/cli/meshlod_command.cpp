#include "cli/meshlod_command.h"

#include "cli/cli_common.h"
#include "core/mesh/mesh_lod.h"
#include "core/mesh/mesh_lod_report.h"

#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>

namespace mlod::cli {

void MeshLodCommand::attach(CLI::App& app) {
  CLI::App* command = app.add_subcommand(
      "meshlod", "Mesh LOD of the whole skinned mesh, simplified with the poses of its clips in view: triangles, "
                 "vertices and error (cm, bind pose and other animated frames) per triangle ratio");
  command->add_option("FILE", file, "character file with a mesh (any format Assimp reads)")->required();
  command->add_option("--ratio", ratios, "triangle ratio per level, in (0, 1], comma-separated: 0.75,0.5,0.25")
      ->required()
      ->delimiter(',');
  command->add_flag("--json", json,
                    "print one JSON document on stdout (\"max_error\" and \"error_cm\" in cm: bind pose, and max and "
                    "mean over animated frames other than those the simplification saw; \"seconds\": the "
                    "simplification, shared by the levels, plus the level's extraction; measuring excluded)");
  addImportOptions(*command, import);
}

namespace {
// The mesh to simplify: the first skinned mesh, else the first mesh.
const SkinnedMesh* characterMesh(const Asset& asset) {
  for (const SkinnedMesh& mesh : asset.meshes)
    if (mesh.skinned())
      return &mesh;
  return asset.meshes.empty() ? nullptr : &asset.meshes.front();
}
} // namespace

int MeshLodCommand::run() const {
  std::vector<double> values;
  for (std::size_t i = 0; i < ratios.size(); ++i) {
    const std::string what = ratios.size() == 1 ? "--ratio" : "--ratio entry " + std::to_string(i + 1);
    char* end = nullptr;
    const double value = std::strtod(ratios[i].c_str(), &end);
    if (ratios[i].empty() || end != ratios[i].c_str() + ratios[i].size()) {
      printError(file, what + " '" + ratios[i] + "' is not a number");
      return kExitBadInput;
    }
    if (!std::isfinite(value) || !(value > 0.0) || value > 1.0) {
      printError(file, what + " is " + ratios[i] + "; a triangle ratio must be in (0, 1]");
      return kExitBadInput;
    }
    values.push_back(value);
  }

  const std::optional<Asset> asset = importForCommand(file, import);
  if (!asset)
    return kExitBadInput;
  const SkinnedMesh* mesh = characterMesh(*asset);
  if (!mesh) {
    printError(file, "has no mesh to simplify");
    return kExitBadInput;
  }
  const Skeleton* skeleton = mesh->skinned() && !asset->skeleton.empty() ? &asset->skeleton : nullptr;
  const std::span<const Clip> clips = skeleton ? std::span<const Clip>(asset->clips) : std::span<const Clip>();

  const auto start = std::chrono::steady_clock::now();
  Result<MeshLod> lod = MeshLod::build(*mesh, skeleton, clips);
  if (!lod) {
    printError(file, lod.message());
    return kExitBadInput;
  }
  const double buildSeconds = secondsSince(start);

  MeshLodReport report;
  report.file = file;
  report.triangles = mesh->triangleCount();
  report.vertices = mesh->vertexCount();
  report.lockedVertices = lod->progressive().lockedCount();
  for (double ratio : values) {
    const auto levelStart = std::chrono::steady_clock::now();
    const std::size_t collapses =
        lod->progressive().collapsesFor(static_cast<std::size_t>(std::llround(ratio * double(report.triangles))));
    const MeshLevelIndices indices = lod->progressive().level(collapses);
    [[maybe_unused]] const SkinnedMesh extracted = lod->compact(indices);
    const double seconds = buildSeconds + secondsSince(levelStart);
    report.levels.push_back(reportLevel(lod->levelForRatio(ratio), seconds)); // measured outside the time
  }

  if (json) {
    std::cout << meshLodReportJson(report) << std::endl;
    return kExitOk;
  }
  std::printf("file:      %s\nmesh:      %s, %zu vertices, %zu triangles, %d joints\n", file.c_str(),
              mesh->name.c_str(), report.vertices, report.triangles, mesh->boneCount());
  std::printf("welded:    %d vertices, %d locked (non-manifold)\n", lod->progressive().weldedVertexCount(),
              report.lockedVertices);
  std::printf("poses:     simplified with the bind pose and %zu animated poses; error (symmetric max distance, cm) "
              "in the bind pose and %zu other animated poses\n\n",
              lod->simplifyPoses().size() - 1, lod->measurePoses().size());
  std::printf("%8s %10s %10s %12s %12s %12s %14s %10s\n", "ratio", "triangles", "vertices", "bind cm", "anim max cm",
              "anim mean cm", "max error cm", "seconds");
  for (const MeshLodReport::Level& level : report.levels)
    std::printf("%8.3f %10zu %10zu %12.4f %12.4f %12.4f %14.4f %10.4f\n", level.ratio, level.triangles, level.vertices,
                level.bindErrorCm, level.animatedMaxErrorCm, level.animatedMeanErrorCm, level.maxErrorCm,
                level.seconds);
  for (const MeshLodReport::Level& level : report.levels)
    if (!level.warning.empty())
      std::printf("warning:   %s\n", level.warning.c_str());
  return kExitOk;
}

} // namespace mlod::cli
