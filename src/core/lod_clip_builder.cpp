#include "core/lod_clip_builder.h"

#include <string>

namespace mlod {

Result<LodClip> buildLodClip(const Clip& clip, const ClusterSet* clusters, std::optional<bool> looping,
                             std::span<const std::int16_t> parents, int blendFrames, double precisionCm) {
  if (clip.frameCount < 1 || clip.jointCount < 1)
    return Error("clip '" + clip.name + "' has no frames or no joints");
  const std::size_t n = static_cast<std::size_t>(clip.jointCount) * static_cast<std::size_t>(clip.frameCount);
  if (clip.rotations.size() != n || clip.translations.size() != n || clip.scales.size() != n)
    return Error("clip '" + clip.name + "' has tracks of the wrong length");
  std::vector<LodCluster> flat;
  std::vector<std::uint32_t> begin;
  if (clusters && clusters->jointCount() > 0) {
    if (Error error = clusters->validate())
      return Error("clip '" + clip.name + "': " + error.message());
    if (clusters->jointCount() != clip.jointCount || clusters->frameCount != clip.frameCount)
      return Error("clip '" + clip.name + "' has " + std::to_string(clip.jointCount) + " joints and " +
                   std::to_string(clip.frameCount) + " frames; its clusters were made for " +
                   std::to_string(clusters->jointCount()) + " and " + std::to_string(clusters->frameCount));
    begin.reserve(static_cast<std::size_t>(clip.jointCount) + 1);
    for (const std::vector<Cluster>& joint : clusters->joints) {
      begin.push_back(static_cast<std::uint32_t>(flat.size()));
      for (const Cluster& cluster : joint)
        flat.push_back(LodCluster{cluster.first, cluster.last, cluster.key});
    }
    begin.push_back(static_cast<std::uint32_t>(flat.size()));
  }
  LodClipSource source;
  source.fps = clip.fps;
  source.frameCount = clip.frameCount;
  source.jointCount = clip.jointCount;
  source.looping = looping.value_or(clip.looping);
  source.rotations = clip.rotations;
  source.translations = clip.translations;
  source.scales = clip.scales;
  source.clusters = flat;
  source.clusterBegin = begin;
  if (parents.size() == static_cast<std::size_t>(clip.jointCount))
    source.parents = parents;
  source.blendFrames = blendFrames;
  source.precisionCm = precisionCm;
  std::string message;
  std::optional<LodClip> built = LodClip::build(source, &message);
  if (!built)
    return Error("clip '" + clip.name + "': " + message);
  return std::move(*built);
}

Result<std::vector<LodClip>> buildLodClips(const Clip& clip, std::span<const ClusterSet> levels,
                                           std::optional<bool> looping, std::span<const std::int16_t> parents) {
  std::vector<LodClip> out;
  out.reserve(levels.size());
  for (const ClusterSet& level : levels) {
    Result<LodClip> built = buildLodClip(clip, &level, looping, parents);
    if (!built)
      return built.error();
    out.push_back(std::move(built).value());
  }
  return out;
}

std::vector<glm::mat4> paletteInverseBinds(const Skeleton& skeleton) {
  const std::vector<glm::mat4> rest = skeleton.restModelMatrices();
  std::vector<glm::mat4> out(rest.size());
  for (std::size_t j = 0; j < rest.size(); ++j) {
    const std::optional<glm::mat4>& bind = skeleton.joints[j].inverseBind;
    out[j] = bind ? *bind : glm::inverse(rest[j]);
    // the evaluator takes affine matrices: the bottom row exactly 0 0 0 1
    out[j][0][3] = out[j][1][3] = out[j][2][3] = 0.0f;
    out[j][3][3] = 1.0f;
  }
  return out;
}

Result<SkinningMesh> buildSkinningMesh(const SkinnedMesh& mesh, int jointCount) {
  if (!mesh.skinned())
    return Error("mesh '" + mesh.name + "' is not skinned");
  std::string message;
  std::optional<SkinningMesh> built =
      SkinningMesh::build(mesh.positions, mesh.normals, mesh.joints, mesh.weights, jointCount, &message);
  if (!built)
    return Error("mesh '" + mesh.name + "': " + message);
  return std::move(*built);
}

} // namespace mlod
