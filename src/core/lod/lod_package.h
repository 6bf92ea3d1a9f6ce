#pragma once
// What an exporter gets (docs/architecture.md sections 3 and 8): one character's LOD set, fully
// computed. Exporters never recompute anything: every level holds its motion (JPC clusters
// on the full skeleton, bone reduction, the clips on the reduced skeleton), its mesh, the
// runtime clips an engine plays, and the paper's Table 1 per clip.
//
// Built by core from an imported asset (a plain file: the default LOD set,
// LodSet::fromPixelBudget(asset, 1 pixel, 4 levels), docs/architecture.md section 6) or from a
// LOD set, JPC settings and extra clips. A project's package (its LodSet, joint settings, and
// the motions assigned to the character through their mappings) is built one layer up, in
// core/project_package.h: this header knows nothing of Project, so the exporter interface
// (sdk/exporter.h) does not pull the project model into every plugin.
//
// Units: lengths in cm, thresholds and errors E in cm·degrees, time in seconds.

#include "core/asset.h"
#include "core/clip.h"
#include "core/error.h"
#include "core/jpc/jpc.h"
#include "core/jpc/jpc_settings.h"
#include "core/lod/lod_character.h"
#include "core/lod/lod_set.h"
#include "core/skeleton.h"
#include "core/skinned_mesh.h"
#include "runtime/bundle.h"
#include "runtime/lod_clip.h"

#include <glm/glm.hpp>

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace mlod {

// One level of the package.
struct LodPackageLevel {
  int index = 0;     // the level's index in LodPackage::lods
  LodLevel settings; // name, threshold, mesh ratio, switch distance, measured errors
  // The level built (lod_character.h): build.motion.clusters per clip on the full skeleton,
  // build.motion.bones the bone reduction (bones.skeleton: the level's skeleton),
  // build.motion.clips per clip on the level's skeleton, build.motion.mesh the full mesh
  // rebound to it, build.mesh the level's simplified mesh (bound to the level's skeleton).
  // For an asset without clips, the motion is the identity (no joint removed, no clip).
  LevelBuild build;
  // Per clip, what the runtime plays at this level: build.motion.clips[c] (the level's
  // skeleton) with the clusters of build.motion.clusters[c] carried over to the joints
  // that remain. Evaluate with skeleton().parentIndices() and inverseBinds.
  std::vector<LodClip> runtimeClips;
  // Per clip, the clusters runtimeClips[c] was built with (on the level's skeleton).
  std::vector<ClusterSet> runtimeClusters;
  // paletteInverseBinds(skeleton()) (lod_clip_builder.h): one per joint of the level.
  std::vector<glm::mat4> inverseBinds;
  // Per clip, Table 1 of the paper and the joint-position fidelity at this level's threshold
  // (clusters on the full skeleton, as measureLevel() gives them).
  std::vector<JpcLevelResult> metrics;

  // The level's skeleton (the full one without bone reduction).
  const Skeleton& skeleton() const { return build.motion.bones.skeleton; }
  // The level's mesh (simplified, bound to skeleton()), or null without a mesh.
  const SkinnedMesh* mesh() const { return build.mesh ? &build.mesh->mesh : nullptr; }
};

// What a package will hold, known before it is built (which can take minutes): enough for
// an exporter to refuse at once what it cannot write (Exporter::planProblem()).
struct LodPackagePlan {
  int joints = 0;               // of the character's skeleton (0: a mesh alone)
  std::uint64_t clipFrames = 0; // frames of every clip the package plays, summed
  int levels = 0;               // levels exported
  bool withOriginal = true;     // level 0 among them
};

struct LodPackage {
  std::string name;       // the asset's file name without its folder and suffix (valid UTF-8: bad bytes U+FFFD)
  std::string sourcePath; // the asset's file, as imported
  double unitScale = 1.0; // cm per file unit the asset was imported at
  Skeleton skeleton;      // the original skeleton (may be empty for a mesh alone)
  std::optional<SkinnedMesh> mesh; // the character mesh: the asset's first skinned mesh (else its first mesh)
  // Every clip the character plays, on `skeleton`: the asset's own, then the motions
  // assigned to it in a project (retargeted through their mappings).
  std::vector<Clip> clips;
  LodSet lods;     // every level of the set (the selected ones are in `levels`)
  JpcSettings jpc; // alpha, mode and per-joint settings the levels were clustered with
  std::vector<LodPackageLevel> levels; // the selected levels, in the order asked for
};

// Progress of a package build: `fraction` in [0, 1] and what is being done. Returns false
// to cancel (the build then fails with kLodPackageCancelled). Called on the building
// thread. May be empty.
using LodPackageProgress = std::function<bool(double fraction, std::string_view message)>;
inline constexpr const char* kLodPackageCancelled = "cancelled";

// Levels of `lods` as an exporter's --levels names them: empty = every level; else indices
// in range, each at most once. Errors name the bad index.
Result<std::vector<int>> selectLodLevels(const LodSet& lods, std::span<const int> levels);

// A package of `asset` with the LOD set `lods` clustered with `jpc`; `extraClips` (of the
// asset's skeleton) play on the character besides its own clips. Errors: an asset without
// a skeleton or a mesh, a LOD set that does not validate, bad levels, settings or clips,
// cancellation (kLodPackageCancelled). `cancel` (core/cancel.h, may be null; run-time only)
// is looked at by every step (JPC per joint, the progressive mesh's collapses, the poses
// measured, each level): once it is set the build stops within a fraction of a second.
Result<LodPackage> buildLodPackage(const Asset& asset, const LodSet& lods, const JpcSettings& jpc,
                                   std::span<const int> levels = {}, const LodPackageProgress& progress = {},
                                   std::span<const Clip> extraClips = {}, const std::atomic<bool>* cancel = nullptr);

// A plain file's package: the default LOD set LodSet::fromPixelBudget(asset, 1 pixel, 4
// levels) for a character skinned where `skinning` says (LodBudgetOptions::skinning) with
// default JPC settings (zero length 1e-6 file units). `cancel` as above, for the
// budget's search too. `extraClips` (of the asset's skeleton: motions mapped onto it) play
// besides its own clips, and every level holds for them too (LodBudgetOptions::clips).
Result<LodPackage> buildLodPackage(const Asset& asset, std::span<const int> levels = {},
                                   const LodPackageProgress& progress = {}, const std::atomic<bool>* cancel = nullptr,
                                   std::span<const Clip> extraClips = {}, LodSkinning skinning = LodSkinning::Gpu);

// A level's mesh bound to the original skeleton (joint indices of the full skeleton, each
// removed joint's influence already moved to its active ancestor by bone reduction): what a
// format with one skin for every level (glTF) needs. Null without a mesh.
std::optional<SkinnedMesh> levelMeshOnFullSkeleton(const LodPackageLevel& level);

// How a bundle's clips are built: the unfreeze blending the engine plays them with and the
// quantization's precision (LodClipSource::blendFrames and precisionCm).
struct BundleOptions {
  int blendFrames = kDefaultBundleBlendFrames;
  double precisionCm = kDefaultClipPrecisionCm;
};

// The runtime bundle of a package (runtime/bundle.h, docs/bundle-format.md): per level its
// skeleton, its clips as runtimeClips were built but for `options` (with 0 blend frames and
// the default precision, each equals runtimeClips[c] bit for bit), and its mesh. Errors: a
// level that the bundle format cannot hold (more than 65,535 levels, a clip of the wrong
// size), options out of range.
Result<Bundle> packageBundle(const LodPackage& package, const BundleOptions& options = {});

} // namespace mlod
