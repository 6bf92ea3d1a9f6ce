#pragma once
// `motionlod info FILE.mlodb [--json]`: a runtime bundle described from its binary alone
// (runtime/bundle.h; no import, no manifest): levels, joints, clips, clusters, meshes, and
// the bytes each level takes. A truncated or corrupt bundle is exit 2 with the reader's
// reason. JSON: {"file","format","version","bytes","name","source","joints",
// "bounding_radius_cm","levels":[{"index","name","threshold","mesh_ratio",
// "switch_distance_cm","joints","clips":[{"name","frames","fps","looping","clusters",
// "bytes"}],"mesh":{"vertices","triangles"}|null}],"seconds"}.

#include <string>

namespace mlod::cli {

bool isBundleFile(const std::string& file);
int describeBundle(const std::string& file, bool json);

} // namespace mlod::cli
