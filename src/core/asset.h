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
  // Where unitScale came from: "file" (the file states it, or its format fixes it: glTF in
  // metres), "guessed" (a file without a unit: see io/import_options.h guessUnitPreset()),
  // or "option" (the user's setting).
  std::string unitSource;
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

// The asset's standing height, cm: the vertical (+Y) extent of its meshes in the bind pose,
// or, without a mesh, of its joints in the rest pose; 0 when it has neither.
double standingHeightCm(const Asset& asset);

// Multiplies every length of `asset` by `factor` (> 0, finite): rest and inverse-bind
// translations, clip translations and mesh positions; unitScale follows.
void scaleAssetLengths(Asset& asset, double factor);

// A JSON document describing the asset for people and tools (`motionlod info --json`):
// file, format, unit ("unit_scale", "unit_source", "height_cm"), joints (name, parent), clips (name, frames, fps,
// duration, channels), meshes (vertices, triangles, bones).
std::string describeAssetJson(const Asset& asset, int indent = 2);

} // namespace mlod
