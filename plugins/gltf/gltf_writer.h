#pragma once
// A LodPackage as one glTF 2.0 asset (docs/architecture.md section 8; docs/gltf-extension.md):
// - units: metres (core is in cm: every length is scaled by 0.01), +Y up as imported;
// - the original skeleton as nodes 0 .. J-1 (node j = joint j, its rest transform), one
//   skin over all of them (inverse bind matrices: paletteInverseBinds()), also without a
//   mesh (clients import a skin's joints as an armature); every level's mesh is bound to
//   that one skin (levelMeshOnFullSkeleton(): bone reduction moved the influences of a
//   level's removed joints to their active ancestors and baked the frozen poses into the
//   vertices), so one skeleton plays every level;
// - names engines and DCC tools key on: level n (its place in package.levels) is the node
//   and mesh "<name>_LOD<n>" and the animation "<clip>_LOD<n>" of each clip;
// - per level and clip one animation: the level's motion M'(t) on the full skeleton, keyed
//   on the source's frames (frame i at i / fps s), with extras {fps, frameCount, clip,
//   looping, level, levelName}. A clustered span [first, last] holds the cluster's key
//   posture: two keys at frames first and last, or, where a track keyed at every frame
//   takes fewer bytes (its key times are shared), the held posture at every frame of the
//   span. Joints removed by bone reduction hold their frozen rotation; everything else is
//   keyed at every frame. Every joint is keyed, whether the clip moves it or not
//   (levelTracks(), core/lod/held_keys.h: a joint a mapped clip leaves alone holds its rest
//   rotation by two keys), so one animation played after another leaves none of its pose;
//   LINEAR, so it plays like the runtime's LodClip (which nlerps where glTF slerps: the
//   same at every frame, within a hair between frames);
//   animation data that repeats (key times; a track a coarser level leaves as it was) is
//   stored once and its accessor shared;
// - a level's mesh: one primitive per part (source mesh), named in the mesh's extras.parts,
//   its triangles ordered for the vertex cache and its vertices for fetch (meshoptimizer);
// - mesh levels: one node per level with a mesh; the first written level's node is in the
//   scene and carries MSFT_lod {"ids": [the other levels' nodes]} and
//   extras.MSFT_screencoverage (per level, the fraction of the viewport height the
//   character's bounding sphere spans, under the LOD set's projection, at the switch
//   distance of the next level: R / (d tan(fov / 2)); 0 for the last). Where the set has
//   no bounding radius or a level no switch distance there is no coverage array, and
//   WriteStats::warnings says so (a made-up 1 would show the coarsest level at any size);
// - the cluster tables and bone reduction of every level in the vendor extension
//   MLOD_joint_clusters at the asset's top level (docs/gltf-extension.md), never required;
//   nodes and animations named there by index and by name; each clip's clusters at a level
//   one binary table (clusterTable(), core/lod/held_keys.h) behind an accessor, counted in
//   the level's animation bytes.
// - rotation outputs are normalized signed 16-bit integers (glTF core; quantizeRotations(),
//   core/lod/held_keys.h: at most kMaxRotationQuantizationDegrees from the level's keys,
//   which WriteStats states with the joint displacement it bounds), or floats
//   (WriteOptions::floatRotations);
// - Compression::Meshopt: every buffer view encoded by meshoptimizer's codecs
//   (EXT_meshopt_compression, required, with a fallback buffer that holds no data), rotations
//   under its QUATERNION filter and normals under its OCTAHEDRAL filter (8-bit,
//   KHR_mesh_quantization, required). Readers need a meshopt decoder (three.js, Babylon.js,
//   gltf-transform); Blender 3.4 and Assimp 5.2 cannot read it.
// A skeleton without a mesh (BVH) gives the joint nodes, their skin and the animations.

#include "core/error.h"
#include "core/lod/lod_package.h"

#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace mlod::gltf {

inline constexpr const char* kClusterExtension = "MLOD_joint_clusters";
inline constexpr int kClusterExtensionVersion = 2; // 1: cluster tables as JSON arrays (still read)
inline constexpr double kMetresPerCm = 0.01;

enum class Compression { None, Meshopt };

struct WriteOptions {
  bool binary = true;  // .glb; false: .gltf JSON with the buffer embedded as a data URI
  bool pretty = false; // indent the JSON of a .gltf
  std::string generator = "Motion LOD Studio";
  // Which of package.levels to write, in order (each at most once); empty = every level. A
  // level keeps its name <name>_LOD<n> (n: its place in package.levels) whichever are written.
  std::vector<std::size_t> levels;
  Compression compression = Compression::None;
  // Rotation outputs as 32-bit floats instead of normalized 16-bit integers (for readers that
  // misread the latter, as Assimp 5.2 does); not with Compression::Meshopt.
  bool floatRotations = false;
};

// What the animations of one written level hold.
struct LevelStats {
  std::string name;               // <name>_LOD<n>
  std::size_t animationBytes = 0; // bytes of key times, values and cluster tables of its animations (shared:
                                  // once; compressed: as stored)
  std::size_t rotationKeys = 0;   // rotation keys, all joints and clips
  std::size_t heldTracks = 0;     // tracks keyed at fewer than every frame (frozen spans held by their ends)
};
struct WriteStats {
  std::vector<LevelStats> levels;    // per written level, in order
  // What storing the rotations as 16-bit integers adds to the levels' motion error: the largest
  // angle between a key and the rotation a reader decodes (degrees; <= kMaxRotationQuantizationDegrees
  // without compression), and the most any joint can move by it (cm, rotationQuantizationBoundCm()).
  double rotationErrorDegrees = 0.0;
  double rotationErrorCm = 0.0;
  std::vector<std::string> warnings; // what the file lacks that a reader may look for, one sentence each
};

// Progress: fraction in [0, 1] and what is being done; returns false to cancel. May be empty.
using WriteProgress = std::function<bool(double fraction, std::string_view message)>;
inline constexpr const char* kWriteCancelled = "cancelled";

// The bytes of the file. Errors: a package whose parts do not fit together (a clip or
// cluster set of another skeleton, a mesh joint out of range), cancellation
// (message kWriteCancelled), a failure of the serializer.
// `out_stats` (may be null) receives what each level's animations hold.
Result<std::string> writeGltf(const LodPackage& package, const WriteOptions& options = {},
                              const WriteProgress& progress = {}, WriteStats* out_stats = nullptr);

} // namespace mlod::gltf
