#include "core/asset.h"

#include <nlohmann/json.hpp>

namespace mlod {

std::string describeAssetJson(const Asset& asset, int indent) {
  using nlohmann::json;
  json doc;
  doc["file"] = asset.sourcePath;
  doc["format"] = asset.format;
  doc["unit_scale"] = asset.unitScale;
  doc["unit_source"] = asset.unitSource;
  doc["height_cm"] = standingHeightCm(asset);
  json joints = json::array();
  for (const Joint& joint : asset.skeleton.joints)
    joints.push_back({{"name", joint.name},
                      {"parent", joint.parent >= 0 ? json(asset.skeleton.joints[std::size_t(joint.parent)].name)
                                                   : json(nullptr)},
                      {"bound", joint.inverseBind.has_value()}});
  doc["joints"] = std::move(joints);
  json clips = json::array();
  for (std::size_t c = 0; c < asset.clips.size(); ++c) {
    const Clip& clip = asset.clips[c];
    json item = {{"name", clip.name},
                 {"frames", clip.frameCount},
                 {"fps", clip.fps},
                 {"duration", clip.durationSeconds()},
                 {"rotation_channels", clip.rotationChannelCount()}};
    if (c < asset.clusters.size()) // the clusters the file carries (a glTF's MLOD_joint_clusters)
      item["clusters"] = asset.clusters[c].clusterCount();
    clips.push_back(std::move(item));
  }
  doc["clips"] = std::move(clips);
  json meshes = json::array();
  for (const SkinnedMesh& mesh : asset.meshes)
    meshes.push_back({{"name", mesh.name},
                      {"vertices", mesh.vertexCount()},
                      {"triangles", mesh.triangleCount()},
                      {"bones", mesh.boneCount()},
                      {"parts", mesh.parts.size()}});
  doc["meshes"] = std::move(meshes);
  doc["warnings"] = asset.warnings;
  return doc.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace); // a file name kept as bytes
}

} // namespace mlod
