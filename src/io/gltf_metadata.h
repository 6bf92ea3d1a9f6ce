#pragma once
// What a glTF that Motion LOD Studio wrote says beyond what Assimp reads
// (docs/gltf-extension.md): each animation's source frame rate and frame count (its extras,
// or the MLOD_joint_clusters extension) and the joint clusters of MLOD_joint_clusters.
// Read from the JSON alone; any other glTF simply states nothing. And what Assimp 5.2.5 reads
// wrong in any glTF: rotation keys stored as normalized integers (glTF core allows BYTE and
// SHORT normalized rotation outputs; the exporter writes SHORT), whose integers Assimp takes
// as float bits; they are decoded here from the file's buffer, for the importer to put in.

#include "core/jpc/cluster_set.h"

#include <glm/gtc/quaternion.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace mlod {

struct GltfAnimationInfo {
  std::string name;              // the glTF animation's name
  std::optional<double> fps;     // frames per second, > 0
  std::optional<int> frameCount; // frames of the source clip, >= 1
  std::optional<bool> looping;
  // The joints with clusters, by node name, each with its clusters as written (unchecked).
  std::vector<std::pair<std::string, std::vector<Cluster>>> clusters;
  // The rotation channels whose keys the file stores as normalized integers, by target node
  // name (Assimp's: "nodes_<i>" for a node without one), each with its keys decoded
  // (i / 32767 for SHORT, i / 127 for BYTE, at least -1; normalized), in key order.
  std::vector<std::pair<std::string, std::vector<glm::quat>>> normalizedRotations;
  // Non-empty when such keys exist but cannot be decoded (an external or sparse buffer):
  // why, one sentence. The importer then refuses the file rather than play Assimp's garbage.
  std::string normalizedRotationProblem;
};

// The extensions the glTF `bytes` (a .glb, or the JSON of a .gltf) requires
// (extensionsRequired); empty for anything else.
std::vector<std::string> requiredGltfExtensions(std::string_view bytes);

// Per animation of the glTF `bytes` (a .glb, or the JSON of a .gltf), in the file's order.
// Empty when the bytes are neither, or state nothing about any animation. References of
// MLOD_joint_clusters are resolved by name where the name and the index disagree (a tool
// renumbered the file); what cannot be resolved is skipped and said in `out_warnings`. A
// file of levels (an animation whose extras name its level, or a node with MSFT_lod) without
// MLOD_joint_clusters lost its cluster tables (a tool that rewrote it: gltf-transform copy or
// prune drops vendor extensions): `out_warnings` says so, rather than showing no cluster.
std::vector<GltfAnimationInfo> readGltfAnimationInfo(std::string_view bytes, std::vector<std::string>& out_warnings);

} // namespace mlod
