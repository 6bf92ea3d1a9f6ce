#include "core/lod/lod_package.h"

#include "core/cancel.h"
#include "core/lod_clip_builder.h"
#include "core/mesh/mesh_lod.h"
#include "core/utf8.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>

namespace mlod {

namespace {

const SkinnedMesh* skinnedMesh(const Asset& asset) {
  for (const SkinnedMesh& mesh : asset.meshes)
    if (mesh.skinned())
      return &mesh;
  return nullptr;
}

// Reports progress; false when the caller cancelled (the flag or the callback).
bool step(const LodPackageProgress& progress, const std::atomic<bool>* cancel, double fraction,
          std::string_view message) {
  return !cancelled(cancel) && (!progress || progress(std::clamp(fraction, 0.0, 1.0), message));
}

// No joint removed: the level's skeleton is the full one.
BoneReduction identityReduction(const Skeleton& skeleton) {
  BoneReduction out;
  for (std::size_t j = 0; j < skeleton.joints.size(); ++j) {
    const int index = static_cast<int>(j);
    out.removed.push_back(0);
    out.activeAncestor.push_back(index);
    out.frozenRotation.push_back(skeleton.joints[j].rest.rotation);
    out.frozenError.push_back(0.0);
    out.reducedIndex.push_back(index);
    out.fullIndex.push_back(index);
  }
  out.skeleton = skeleton;
  return out;
}

// The clusters of the full skeleton carried over to the joints that remain at a level.
ClusterSet reducedClusters(const BoneReduction& bones, const ClusterSet& full) {
  ClusterSet out;
  out.frameCount = full.frameCount;
  out.joints.reserve(bones.fullIndex.size());
  for (int fullJoint : bones.fullIndex)
    out.joints.push_back(full.joints.empty() ? std::vector<Cluster>{} : full.joints[std::size_t(fullJoint)]);
  return out;
}

// The original as a level: the full skeleton, the clips unclustered, the full mesh.
LevelBuild originalLevel(const LodPackage& package) {
  LevelBuild out;
  out.motion.bones = identityReduction(package.skeleton);
  out.motion.clips = package.clips;
  for (const Clip& clip : package.clips) {
    ClusterSet none;
    none.frameCount = clip.frameCount;
    none.joints = std::vector<std::vector<Cluster>>(std::size_t(clip.jointCount));
    out.motion.clusters.push_back(std::move(none));
  }
  if (package.mesh) {
    out.motion.mesh = *package.mesh;
    MeshLodLevel full;
    full.targetTriangles = package.mesh->triangleCount();
    full.mesh = *package.mesh;
    for (std::size_t v = 0; v < package.mesh->vertexCount(); ++v)
      full.sourceVertices.push_back(static_cast<std::uint32_t>(v));
    out.mesh = std::move(full);
  }
  return out;
}

std::string stemOf(const std::string& path) {
  // a name, not a file name: valid UTF-8 (core/utf8.h), as glTF and JSON need it
  return validUtf8(std::filesystem::path(path).stem().string());
}

} // namespace

Result<std::vector<int>> selectLodLevels(const LodSet& lods, std::span<const int> levels) {
  std::vector<int> out;
  if (levels.empty()) {
    for (int i = 0; i < static_cast<int>(lods.levels.size()); ++i)
      out.push_back(i);
    return out;
  }
  std::set<int> seen;
  for (int level : levels) {
    if (level < 0 || level >= static_cast<int>(lods.levels.size()))
      return Error("level " + std::to_string(level) + " does not exist (the LOD set has " +
                   std::to_string(lods.levels.size()) + " levels, 0 to " + std::to_string(lods.levels.size() - 1) + ")");
    if (!seen.insert(level).second)
      return Error("level " + std::to_string(level) + " is named twice");
    out.push_back(level);
  }
  return out;
}

// buildLodPackage() below, without the mapping of a cancel below it to kLodPackageCancelled.
static Result<LodPackage> assemblePackage(const Asset& asset, const LodSet& lods, const JpcSettings& jpc,
                                          std::span<const int> levels, const LodPackageProgress& progress,
                                          std::span<const Clip> extraClips, const std::atomic<bool>* cancel) {
  if (Error error = asset.validate())
    return Error("asset: " + error.message());
  if (Error error = lods.validate())
    return error;
  Result<std::vector<int>> selected = selectLodLevels(lods, levels);
  if (!selected)
    return selected.error();
  if (!asset.skeleton.empty())
    if (Error error = jpc.validate(asset.skeleton))
      return error;
  for (const Clip& clip : extraClips)
    if (Error error = clip.validate(asset.skeleton))
      return Error("clip '" + clip.name + "': " + error.message());

  LodPackage out;
  out.name = stemOf(asset.sourcePath);
  out.sourcePath = asset.sourcePath;
  out.unitScale = asset.unitScale;
  out.skeleton = asset.skeleton;
  out.lods = lods;
  out.jpc = jpc;
  out.clips = asset.clips;
  out.clips.insert(out.clips.end(), extraClips.begin(), extraClips.end());
  const SkinnedMesh* skinned = skinnedMesh(asset);
  if (skinned)
    out.mesh = *skinned;
  else if (!asset.meshes.empty())
    out.mesh = asset.meshes.front();
  if (out.clips.empty() && !out.mesh)
    return Error("LOD: the asset has neither a clip to simplify nor a mesh");
  if (!step(progress, cancel, 0.0, "preparing " + out.name))
    return Error(kLodPackageCancelled);

  const double total = static_cast<double>(selected->size()) + 1.0;
  const bool motion = !out.clips.empty() && !out.skeleton.empty();
  std::optional<LodCharacter> character;
  std::vector<JpcClip> prepared;
  std::optional<MeshLod> meshOnly; // an asset without a clip: its mesh's levels alone
  if (motion) {
    Result<LodCharacter> built = LodCharacter::prepare(out.skeleton, skinned, out.clips, jpc, {}, cancel);
    if (!built)
      return built.error();
    character = std::move(built).value();
    for (const Clip& clip : out.clips) {
      if (cancelled(cancel))
        return Error(kLodPackageCancelled);
      Result<JpcClip> clipPrepared = JpcClip::prepare(out.skeleton, clip, jpc);
      if (!clipPrepared)
        return Error("clip '" + clip.name + "': " + clipPrepared.message());
      prepared.push_back(std::move(clipPrepared).value());
    }
  } else {
    MeshLodSettings settings;
    settings.cancel = cancel;
    Result<MeshLod> built = MeshLod::build(*out.mesh, out.skeleton.empty() ? nullptr : &out.skeleton, {}, settings);
    if (!built)
      return built.error();
    meshOnly = std::move(built).value();
  }

  for (std::size_t i = 0; i < selected->size(); ++i) {
    const int index = (*selected)[i];
    const LodLevel& settings = lods.levels[std::size_t(index)];
    if (!step(progress, cancel, (static_cast<double>(i) + 1.0) / total, "building level " + settings.name))
      return Error(kLodPackageCancelled);
    LodPackageLevel level;
    level.index = index;
    level.settings = settings;
    if (index == 0) {
      // the original (LodSet::validate(): threshold 0, ratio 1): every joint, nothing
      // clustered (docs/architecture.md section 4: the "Original" column is 0 by definition)
      level.build = originalLevel(out);
      for (std::size_t c = 0; c < out.clips.size(); ++c) {
        if (cancelled(cancel))
          return Error(kLodPackageCancelled);
        Result<LodClip> runtime = buildLodClip(out.clips[c], nullptr, std::nullopt, out.skeleton.parentIndices());
        if (!runtime)
          return Error("level " + settings.name + ": " + runtime.message());
        level.runtimeClips.push_back(std::move(runtime).value());
        level.runtimeClusters.push_back(level.build.motion.clusters[c]);
        level.metrics.push_back(measureLevel(prepared[c], out.skeleton, out.clips[c], 0, 0.0,
                                             std::vector<JointClustering>(out.skeleton.joints.size())));
      }
    } else if (motion) {
      Result<LevelBuild> build = character->build(settings.motionThreshold, settings.meshRatio, index);
      if (!build)
        return Error("level " + settings.name + ": " + build.message());
      level.build = std::move(build).value();
      const LevelMotion& levelMotion = level.build.motion;
      for (std::size_t c = 0; c < out.clips.size(); ++c) {
        if (cancelled(cancel))
          return Error(kLodPackageCancelled);
        ClusterSet clusters = reducedClusters(levelMotion.bones, levelMotion.clusters[c]);
        Result<LodClip> runtime =
            buildLodClip(levelMotion.clips[c], &clusters, std::nullopt, levelMotion.bones.skeleton.parentIndices());
        if (!runtime)
          return Error("level " + settings.name + ": " + runtime.message());
        level.runtimeClips.push_back(std::move(runtime).value());
        level.runtimeClusters.push_back(std::move(clusters));
        level.metrics.push_back(measureLevel(prepared[c], out.skeleton, out.clips[c], index, settings.motionThreshold,
                                             prepared[c].cluster(index, settings.motionThreshold, 0, cancel)));
      }
    } else {
      level.build = originalLevel(out);
      level.build.motion.threshold = settings.motionThreshold;
      level.build.mesh = meshOnly->levelForRatio(settings.meshRatio);
    }
    level.inverseBinds = paletteInverseBinds(level.skeleton());
    out.levels.push_back(std::move(level));
  }
  if (!step(progress, cancel, 1.0, "done"))
    return Error(kLodPackageCancelled);
  return out;
}

Result<LodPackage> buildLodPackage(const Asset& asset, const LodSet& lods, const JpcSettings& jpc,
                                   std::span<const int> levels, const LodPackageProgress& progress,
                                   std::span<const Clip> extraClips, const std::atomic<bool>* cancel) {
  Result<LodPackage> out = assemblePackage(asset, lods, jpc, levels, progress, extraClips, cancel);
  // note: a step below that saw the flag returns kCancelled, or levels measured after it
  // (their errors unmeasured): either way the package is cancelled
  if (cancelled(cancel))
    return Error(kLodPackageCancelled);
  return out;
}

Result<LodPackage> buildLodPackage(const Asset& asset, std::span<const int> levels, const LodPackageProgress& progress,
                                   const std::atomic<bool>* cancel, std::span<const Clip> extraClips,
                                   LodSkinning skinning) {
  if (!step(progress, cancel, 0.0, "generating the default LOD set"))
    return Error(kLodPackageCancelled);
  // the budget's search is the first half of the work, the levels the second; a cancel
  // during either stops it at once
  LodBudgetOptions options;
  options.jpc.zeroLength = 1e-6 * asset.unitScale; // docs/architecture.md section 4: 1e-6 file units
  options.progress = [&](double fraction) {
    return step(progress, cancel, 0.5 * fraction, "generating the default LOD set");
  };
  options.cancel = cancel;
  options.clips = extraClips;
  options.skinning = skinning;
  Result<LodSet> lods = LodSet::fromPixelBudget(asset, 1.0, 4, options);
  if (!lods)
    return lods.message() == kLodBudgetCancelled ? Error(kLodPackageCancelled) : lods.error();
  return buildLodPackage(
      asset, *lods, options.jpc, levels,
      [&](double fraction, std::string_view message) { return step(progress, cancel, 0.5 + 0.5 * fraction, message); },
      extraClips, cancel);
}

Result<Bundle> packageBundle(const LodPackage& package, const BundleOptions& options) {
  if (options.blendFrames < 0 || options.blendFrames > kMaxBlendFrames)
    return Error("bundle: blend frames " + std::to_string(options.blendFrames) + " is not in [0, " +
                 std::to_string(kMaxBlendFrames) + "]");
  if (!std::isfinite(options.precisionCm) || options.precisionCm <= 0.0 || options.precisionCm > 1e3)
    return Error("bundle: precision " + std::to_string(options.precisionCm) + " cm is not in (0, 1000]");
  Bundle out;
  out.name = package.name.empty() ? std::string("character") : package.name;
  out.source = package.sourcePath;
  out.verticalFovDegrees = package.lods.projection.verticalFovDegrees;
  out.viewportHeightPixels = package.lods.projection.viewportHeightPixels;
  out.boundingRadiusCm = package.lods.boundingRadiusCm;
  for (const Joint& joint : package.skeleton.joints) {
    out.jointNames.push_back(joint.name);
    out.jointParents.push_back(static_cast<std::int16_t>(joint.parent));
  }
  for (const LodPackageLevel& level : package.levels) {
    BundleLevel b;
    b.index = level.index;
    b.name = level.settings.name;
    b.motionThreshold = level.settings.motionThreshold;
    b.meshRatio = level.settings.meshRatio;
    b.switchDistanceCm = level.settings.switchDistanceCm;
    b.pixelError = level.settings.pixelError;
    b.screenSizePixels = level.settings.screenSizePixels;
    b.motionErrorCm = level.settings.motionErrorCm;
    b.meshErrorCm = level.settings.meshErrorCm;
    const Skeleton& skeleton = level.skeleton();
    b.parents = skeleton.parentIndices();
    b.inverseBinds = level.inverseBinds;
    for (int full : level.build.motion.bones.fullIndex)
      b.fullJoints.push_back(full);
    for (std::size_t c = 0; c < level.runtimeClips.size(); ++c) {
      const Clip& clip = level.build.motion.clips[c];
      const ClusterSet& clusters = level.runtimeClusters[c];
      Result<LodClip> built = buildLodClip(clip, clusters.jointCount() > 0 ? &clusters : nullptr, std::nullopt,
                                           b.parents, options.blendFrames, options.precisionCm);
      if (!built)
        return Error("bundle: level '" + b.name + "': " + built.message());
      b.clips.push_back(BundleClip{clip.name, std::move(built).value()});
    }
    if (const SkinnedMesh* mesh = level.mesh(); mesh && mesh->skinned()) {
      BundleMesh m;
      m.positions = mesh->positions;
      m.normals = mesh->normals;
      m.indices = mesh->indices;
      m.joints = mesh->joints;
      m.weights = mesh->weights;
      b.mesh = std::move(m);
    }
    out.levels.push_back(std::move(b));
  }
  if (std::string problem = validateBundle(out); !problem.empty())
    return Error("bundle: " + problem);
  return out;
}

std::optional<SkinnedMesh> levelMeshOnFullSkeleton(const LodPackageLevel& level) {
  const SkinnedMesh* mesh = level.mesh();
  if (!mesh)
    return std::nullopt;
  SkinnedMesh out = *mesh;
  const std::vector<int>& full = level.build.motion.bones.fullIndex;
  for (std::size_t v = 0; v < out.joints.size(); ++v)
    for (int k = 0; k < kMaxInfluences; ++k)
      if (std::size_t(out.joints[v][k]) < full.size())
        out.joints[v][k] = static_cast<std::uint16_t>(full[out.joints[v][k]]);
  return out;
}

} // namespace mlod
