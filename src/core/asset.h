#pragma once
// What one imported file gave: a skeleton, its clips and its meshes, in cm.

#include "core/clip.h"
#include "core/error.h"
#include "core/jpc/cluster_set.h"
#include "core/skeleton.h"
#include "core/skinned_mesh.h"

#include <string>
#include <vector>

namespace mlod {

class Asset {
public:
  std::string sourcePath;       // the file it came from, as given
  std::string format;           // the importer that read it, e.g. "BVH", "X", "glTF2"
  double unitScale = 1.0;       // cm per file unit, already applied to every length
  std::string unitSource;       // where unitScale came from: "file", "format", "option", "default"
  Skeleton skeleton;            // may be empty (a mesh without a skeleton)
  std::vector<Clip> clips;      // each animates every joint of the skeleton
  std::vector<SkinnedMesh> meshes; // the character mesh (skinned) and/or a static mesh
  // Per clip, the joint clusters the file carries (a glTF's MLOD_joint_clusters,
  // docs/gltf-extension.md); empty when the file carries none.
  std::vector<ClusterSet> clusters;
  std::vector<std::string> warnings; // what the importer noticed and worked around

  // Rules: unitScale finite and > 0; the skeleton validates; every clip validates
  // against it; every mesh validates against its joint count; a clip needs a
  // skeleton; the asset holds at least a skeleton or a mesh; clusters is empty or holds one
  // set per clip, each of the skeleton's joints and the clip's frames, and validates.
  Error validate() const;
};

// A JSON document describing the asset for people and tools (`motionlod info --json`):
// file, format, unit, joints (name, parent), clips (name, frames, fps, duration,
// channels), meshes (vertices, triangles, bones).
std::string describeAssetJson(const Asset& asset, int indent = 2);

} // namespace mlod
