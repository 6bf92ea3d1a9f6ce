#include "core/lod/lod_set.h"

#include "core/cancel.h"
#include "core/lod/lod_character.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <span>
#include <thread>
#include <tuple>

namespace mlod {

namespace {

const SkinnedMesh* characterMesh(const Asset& asset) {
  for (const SkinnedMesh& mesh : asset.meshes)
    if (mesh.skinned())
      return &mesh;
  return nullptr;
}

bool hasThresholdOverrides(const JpcSettings& settings) {
  return std::any_of(settings.joints.begin(), settings.joints.end(),
                     [](const auto& entry) { return !entry.second.thresholds.empty(); });
}

// The mesh ratio of each level 1 .. levels - 1 (docs/architecture.md section 5): spread
// evenly in log scale from the original down to the smallest candidate, each snapped to the
// nearest candidate below the previous level's, so the far levels are the coarse ones (4
// levels of the default candidates: 0.5, 0.2, 0.1). Where the candidates run out, the last
// is repeated.
std::vector<double> levelRatios(std::span<const double> candidates, int levels) {
  std::vector<double> out;
  if (candidates.empty() || levels < 2)
    return out;
  const double coarsest = candidates.back();
  double previous = 1.0;
  for (int i = 1; i < levels; ++i) {
    const double aim = std::pow(coarsest, double(i) / double(levels - 1));
    double best = 0.0, bestDistance = std::numeric_limits<double>::max();
    for (double candidate : candidates)
      if (candidate < previous && std::fabs(std::log(candidate / aim)) < bestDistance)
        best = candidate, bestDistance = std::fabs(std::log(candidate / aim));
    if (best == 0.0)
      best = coarsest;
    out.push_back(best);
    previous = best;
  }
  return out;
}

// Reports the fraction done (LodBudgetOptions::progress); false once the caller cancelled.
class Progress {
public:
  Progress(const std::function<bool(double)>& callback, const std::atomic<bool>* cancel)
      : m_callback(callback), m_cancel(cancel) {}
  bool operator()(double fraction) {
    if (!m_cancelled && (cancelled(m_cancel) || (m_callback && !m_callback(std::clamp(fraction, 0.0, 1.0)))))
      m_cancelled = true;
    return !m_cancelled;
  }

private:
  const std::function<bool(double)>& m_callback;
  const std::atomic<bool>* m_cancel;
  bool m_cancelled = false;
};

std::string figure(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", value);
  return text;
}

// The rules every generated level keeps (lod_set.h): beyond level 0 no threshold of 0 where
// there is a motion to simplify, and no repeat (same threshold and mesh ratio) of the level
// kept before it. The reason `level` is left out, or "" to keep it.
std::string whyLeftOut(const LodLevel& level, const LodLevel& previous, bool hasMotion) {
  if (hasMotion && level.motionThreshold == 0.0)
    return "no threshold above 0 keeps its motion within the budget";
  if (level.motionThreshold == previous.motionThreshold && level.meshRatio == previous.meshRatio)
    return "it would repeat " + previous.name + " (E " + figure(level.motionThreshold) + " cm·°, mesh ratio " +
           figure(level.meshRatio) + ")";
  return {};
}

// Keeps `level` (named after its position) or reports why it is left out. True when kept.
bool keepLevel(LodSet& out, LodLevel level, int aimed, bool hasMotion, LodBudgetReport* report,
               double simplifiedPercent) {
  const std::string why = whyLeftOut(level, out.levels.back(), hasMotion);
  if (!why.empty()) {
    if (report)
      report->dropped.push_back("Aimed level " + std::to_string(aimed) + " is left out: " + why + ".");
    return false;
  }
  level.name = "LOD" + std::to_string(out.levels.size());
  out.levels.push_back(std::move(level));
  if (report)
    report->simplifiedPercent.push_back(simplifiedPercent);
  return true;
}

// Levels for a character that plays no clip (or a mesh without a skeleton): the mesh alone,
// in its bind pose, no motion to simplify and no joint to remove.
Result<LodSet> meshOnly(const Asset& asset, double pixels, int levels, const LodBudgetOptions& options,
                        LodBudgetReport* report, Progress& progress) {
  const SkinnedMesh* mesh = asset.meshes.empty() ? nullptr : &asset.meshes.front();
  for (const SkinnedMesh& candidate : asset.meshes)
    if (candidate.skinned()) {
      mesh = &candidate;
      break;
    }
  if (!mesh)
    return Error("LOD: the asset has neither a clip to simplify nor a mesh");
  const Skeleton* skeleton = asset.skeleton.empty() ? nullptr : &asset.skeleton;
  Result<MeshLod> lod = MeshLod::build(*mesh, skeleton, {}, options.mesh);
  if (!lod)
    return lod.error();
  LodSet out;
  out.projection = options.projection;
  out.skinning = options.skinning;
  const glm::vec3 centre = skeleton ? glm::vec3(skeleton->restModelMatrices()[0][3]) : glm::vec3(0.0f);
  for (const glm::vec3& p : mesh->positions)
    out.boundingRadiusCm = std::max(out.boundingRadiusCm, double(glm::length(p - centre)));
  LodLevel original;
  original.name = "LOD0";
  original.triangles = static_cast<int>(mesh->triangleCount());
  original.activeJoints = asset.skeleton.jointCount();
  out.levels.push_back(original);
  if (report)
    report->simplifiedPercent.push_back(0.0);
  double previousDistance = 0.0;
  const std::vector<double> ratios = levelRatios(options.meshRatios, levels);
  for (int i = 1; i < levels; ++i) {
    if (!progress(double(i - 1) / double(levels - 1)))
      return Error(kLodBudgetCancelled);
    const MeshLodLevel level = lod->levelForRatio(ratios[std::size_t(i - 1)]);
    LodLevel entry = original;
    entry.meshRatio = double(level.triangles()) / double(mesh->triangleCount());
    entry.meshErrorCm = level.maxErrorCm;
    entry.triangles = static_cast<int>(level.triangles());
    entry.switchDistanceCm = std::max(
        previousDistance, distanceForPixels(entry.deviationCm(), pixels, out.boundingRadiusCm, options.projection));
    entry.pixelError =
        deviationPixels(entry.deviationCm(), entry.switchDistanceCm, out.boundingRadiusCm, options.projection);
    entry.screenSizePixels = screenSizePixels(out.boundingRadiusCm, entry.switchDistanceCm, options.projection);
    if (keepLevel(out, entry, i, false, report, 0.0))
      previousDistance = entry.switchDistanceCm;
  }
  progress(1.0);
  return out;
}

// A level of a progressive mesh, as the search reads it.
struct MeshFigures {
  double maxErrorCm = 0.0;
  std::size_t triangles = 0;
};

bool sameMeshSettings(const MeshLodSettings& a, const MeshLodSettings& b) {
  const ProgressiveMeshSettings &x = a.simplification, &y = b.simplification;
  return x.borderWeight == y.borderWeight && x.seamWeight == y.seamWeight && x.skinWeight == y.skinWeight &&
         x.moveWeight == y.moveWeight && a.samplingSpacingCm == b.samplingSpacingCm &&
         a.simplifyPoses == b.simplifyPoses && a.measurePoses == b.measurePoses &&
         a.jointImportance == b.jointImportance;
}

bool sameSkeleton(const Skeleton& a, const Skeleton& b) {
  return std::equal(
      a.joints.begin(), a.joints.end(), b.joints.begin(), b.joints.end(), [](const Joint& x, const Joint& y) {
        return x.name == y.name && x.parent == y.parent && x.rest.translation == y.rest.translation &&
               x.rest.rotation == y.rest.rotation && x.rest.scale == y.rest.scale && x.inverseBind == y.inverseBind;
      });
}

bool sameClip(const Clip& a, const Clip& b) {
  return a.name == b.name && a.fps == b.fps && a.frameCount == b.frameCount && a.jointCount == b.jointCount &&
         a.looping == b.looping && a.rotations == b.rotations && a.translations == b.translations &&
         a.scales == b.scales && a.hasRotation == b.hasRotation && a.hasTranslation == b.hasTranslation &&
         a.hasScale == b.hasScale;
}

bool sameMesh(const SkinnedMesh* a, const std::optional<SkinnedMesh>& b) {
  if (!a || !b)
    return !a && !b;
  return a->positions == b->positions && a->normals == b->normals && a->uvs == b->uvs && a->indices == b->indices &&
         a->joints == b->joints && a->weights == b->weights;
}

} // namespace

struct LodBudgetCache::State {
  LodCharacter character;
  std::map<std::pair<int, double>, LevelMotion> motions;         // by (level slot, threshold), as the search keys them
  std::map<std::pair<int, double>, MeshLod> meshes;              // of the motion of the same key
  std::map<std::tuple<int, double, double>, MeshFigures> levels; // (slot, threshold, ratio)

  // Holds what a run with these inputs computes.
  bool answers(const Skeleton& skeleton, const SkinnedMesh* mesh, std::span<const Clip> clips,
               const MeshLodSettings& meshSettings) const {
    return sameSkeleton(character.skeleton(), skeleton) && sameMesh(mesh, character.mesh()) &&
           std::equal(clips.begin(), clips.end(), character.clips().begin(), character.clips().end(), sameClip) &&
           sameMeshSettings(character.meshSettings(), meshSettings);
  }
  // Nothing kept refers to a run's cancel flag once the run is over.
  void setCancel(const std::atomic<bool>* cancel) {
    character.setCancel(cancel);
    for (auto& entry : meshes)
      entry.second.setCancel(cancel);
  }
};

LodBudgetCache::LodBudgetCache() = default;
LodBudgetCache::~LodBudgetCache() = default;
LodBudgetCache::LodBudgetCache(LodBudgetCache&&) noexcept = default;
LodBudgetCache& LodBudgetCache::operator=(LodBudgetCache&&) noexcept = default;
void LodBudgetCache::clear() {
  m_state.reset();
}

class LodBudgetRun {
public:
  static std::unique_ptr<LodBudgetCache::State>& state(LodBudgetCache& cache) { return cache.m_state; }
};

const char* lodSkinningName(LodSkinning skinning) {
  return skinning == LodSkinning::Cpu ? "cpu" : "gpu";
}

std::optional<LodSkinning> lodSkinningFromName(std::string_view name) {
  if (name == "gpu")
    return LodSkinning::Gpu;
  if (name == "cpu")
    return LodSkinning::Cpu;
  return std::nullopt;
}

double motionShareByCost(int joints, std::size_t vertices) {
  const double pose = kPoseCostPerJoint * std::max(joints, 0);
  const double skin = kSkinCostPerVertex * static_cast<double>(vertices);
  if (!(pose + skin > 0.0))
    return kMaxMotionShare;
  return std::clamp(pose / (pose + skin), kMinMotionShare, kMaxMotionShare);
}

// The motion's share of a level's deviation for a character with a mesh: the option's, else
// by where it is skinned (LodBudgetOptions::skinning).
static double meshMotionShare(const LodBudgetOptions& options, int joints, std::size_t vertices) {
  if (options.motionShare)
    return *options.motionShare;
  return options.skinning == LodSkinning::Gpu ? kGpuMotionShare : motionShareByCost(joints, vertices);
}

// fromPixelBudget() with options.mesh.cancel the one flag of the run.
static Result<LodSet> generateLevels(const Asset& asset, double pixels, int levels, const LodBudgetOptions& options,
                                     LodBudgetReport* report) {
  Progress progress(options.progress, options.mesh.cancel);
  if (!std::isfinite(pixels) || !(pixels > 0.0))
    return Error("LOD: the pixel budget must be > 0");
  if (levels < 1)
    return Error("LOD: at least one level (the original)");
  if (Error error = options.projection.validate())
    return error;
  if (options.motionShare && !(*options.motionShare > 0.0 && *options.motionShare <= 1.0))
    return Error("LOD: the motion's share of the budget must be in (0, 1]");
  for (double threshold : options.thresholds)
    if (Error error = validateThreshold(threshold, "candidate threshold"))
      return error;
  for (std::size_t i = 0; i < options.meshRatios.size(); ++i)
    if (!(options.meshRatios[i] > 0.0 && options.meshRatios[i] <= 1.0) ||
        (i > 0 && !(options.meshRatios[i] < options.meshRatios[i - 1])))
      return Error("LOD: candidate mesh ratios must fall, each in (0, 1]");
  std::vector<Clip> clips = asset.clips;
  clips.insert(clips.end(), options.clips.begin(), options.clips.end());
  if (!progress(0.0))
    return Error(kLodBudgetCancelled);
  if (clips.empty() || asset.skeleton.empty())
    return meshOnly(asset, pixels, levels, options, report, progress);
  // The character, its motions and meshes: kept from an earlier run where its inputs were the same.
  std::unique_ptr<LodBudgetCache::State> fresh;
  std::unique_ptr<LodBudgetCache::State>* kept = options.cache ? &LodBudgetRun::state(*options.cache) : nullptr;
  if (kept && *kept && (*kept)->answers(asset.skeleton, characterMesh(asset), clips, options.mesh)) {
    LodBudgetCache::State& state = **kept;
    state.setCancel(options.mesh.cancel);
    if (!(state.character.jpcSettings() == options.jpc)) { // the motions and meshes depend on every joint
      if (Error error = state.character.setJpcSettings(options.jpc))
        return error;
      state.motions.clear();
      state.meshes.clear();
      state.levels.clear();
    }
  } else {
    Result<LodCharacter> prepared =
        LodCharacter::prepare(asset.skeleton, characterMesh(asset), clips, options.jpc, options.mesh);
    if (!prepared)
      return prepared.error();
    fresh = std::make_unique<LodBudgetCache::State>(LodBudgetCache::State{std::move(prepared).value(), {}, {}, {}});
    if (report)
      report->characterPrepared = true;
    if (kept)
      *kept = std::move(fresh); // (a failed run leaves it prepared: that part is finished)
  }
  LodBudgetCache::State& state = kept ? **kept : *fresh;
  LodCharacter* const character = &state.character;
  character->setWorkLimit(options.workLimit);
  const std::int64_t clusteredBefore = character->jointsClustered();
  const auto count = [&] {
    if (report)
      report->jointsClustered = static_cast<int>(character->jointsClustered() - clusteredBefore);
  };
  // Step 4's progressive mesh of the motion of `key`, built once.
  const auto meshFor = [&](std::pair<int, double> key, const LevelMotion& motion) -> Result<MeshLod*> {
    auto found = state.meshes.find(key);
    if (found == state.meshes.end()) {
      Result<MeshLod> lod = character->meshLodFor(motion);
      if (!lod)
        return lod.error();
      if (report)
        ++report->meshesBuilt;
      found = state.meshes.emplace(key, std::move(lod).value()).first;
    }
    return &found->second;
  };
  // Its level at `ratio`, measured once (a measurement after a cancel is not kept).
  const auto levelOf = [&](std::pair<int, double> key, const MeshLod& lod, double ratio) {
    const std::tuple<int, double, double> at{key.first, key.second, ratio};
    if (const auto found = state.levels.find(at); found != state.levels.end())
      return found->second;
    const MeshLodLevel level = lod.levelForRatio(ratio);
    const MeshFigures figures{level.maxErrorCm, level.triangles()};
    if (!cancelled(options.mesh.cancel))
      state.levels.emplace(at, figures);
    return figures;
  };

  LodSet out;
  out.projection = options.projection;
  out.skinning = options.skinning;
  out.boundingRadiusCm = character->boundingRadiusCm();
  const double radius = out.boundingRadiusCm;
  if (!std::isfinite(radius)) // (the skeleton check refuses offsets that overflow; this guards the rest)
    return Error("LOD: the character's bounding radius is not finite (" + std::to_string(radius) +
                 " cm), so a pixel budget gives no switch distance");
  if (!(radius > 0.0)) // a character of no size stays under any pixel budget at any distance
    return Error("LOD: the character has no size (every joint and vertex sits at one point, e.g. a BVH whose "
                 "offsets are all zero), so a pixel budget gives no switch distance; give the levels in a project");
  LodLevel original;
  original.name = "LOD0";
  original.triangles = character->mesh() ? static_cast<int>(character->mesh()->triangleCount()) : 0;
  original.activeJoints = asset.skeleton.jointCount();
  out.levels.push_back(original);
  if (report)
    report->simplifiedPercent.push_back(0.0);
  // Preparing takes about a twentieth of the work; each level an equal share of the rest,
  // its motion search 60% of that (by candidates tried), its mesh the other 40%.
  const auto done = [&](int aimed, double ofLevel) {
    return progress(0.05 + 0.95 * (double(aimed - 1) + ofLevel) / double(std::max(1, levels - 1)));
  };

  std::vector<double> candidates = options.thresholds;
  std::sort(candidates.begin(), candidates.end());
  const bool perLevel = hasThresholdOverrides(options.jpc);
  std::map<std::pair<int, double>, LevelMotion>& motions = state.motions; // by (level for overrides, threshold)
  double previousThreshold = 0.0; // (the previous distance: out.levels.back().switchDistanceCm)
  // note: with a mesh, the mesh leads (docs/architecture.md section 5): each level's ratio
  // comes from levelRatios(), its error is measured on the full motion's mesh LOD, and the
  // motion takes the largest threshold whose error stays within motionShare of the level's
  // deviation (mesh error / (1 - motionShare)); the level then switches where what it
  // measures, motion and mesh rebound to its skeleton, spans N pixels. Without a mesh each
  // level aims where the character is height / 2^i pixels tall.
  const std::vector<double> ratios = levelRatios(options.meshRatios, levels);
  const double motionShare =
      !character->mesh() ? 1.0
                         : meshMotionShare(options, asset.skeleton.jointCount(), character->mesh()->vertexCount());
  if (report)
    report->motionShare = motionShare;
  const MeshLod* fullMotionMesh = nullptr;
  const std::pair<int, double> fullKey{0, 0.0}; // the search's E = 0 at slot 0
  if (character->mesh()) {
    // note: E = 0's motion error is float noise, and measuring it exactly skins every frame;
    // the search mostly compares it with a budget far above it, so it takes the bound first
    // and measures only where the bound decides nothing (settled() below)
    auto full = motions.find(fullKey);
    if (full == motions.end()) {
      Result<LevelMotion> made = character->motionAt(0.0, 0, LodCharacter::MotionError::Bound);
      count();
      if (!made)
        return made.error();
      if (report)
        ++report->motionsMade;
      full = motions.emplace(fullKey, std::move(made).value()).first;
    }
    Result<MeshLod*> lod = meshFor(fullKey, full->second);
    if (!lod)
      return lod.error();
    fullMotionMesh = *lod;
  }
  // note: every level's budget is measured on the full motion's mesh whatever the levels
  // before it decide, so those of levels 2 .. are measured on a thread of their own while
  // level 1 is searched (each into its own slot; kept, as levelOf() keeps them, when the run
  // reaches them uncancelled)
  std::vector<std::optional<MeshFigures>> ahead(ratios.size());
  std::jthread measuringAhead;
  if (fullMotionMesh && ratios.size() > 1) {
    std::vector<std::size_t> wanted;
    for (std::size_t r = 1; r < ratios.size(); ++r)
      if (!state.levels.contains({fullKey.first, fullKey.second, ratios[r]}))
        wanted.push_back(r);
    if (!wanted.empty())
      measuringAhead = std::jthread([&ahead, &ratios, wanted, lod = fullMotionMesh, cancel = options.mesh.cancel] {
        for (const std::size_t r : wanted) {
          if (cancelled(cancel)) // a cancelled run waits for this thread: stop between levels
            return;
          const MeshLodLevel level = lod->levelForRatio(ratios[r]);
          ahead[r] = MeshFigures{level.maxErrorCm, level.triangles()};
        }
      });
  }
  const auto takeAhead = [&] { // the measurements made ahead, as levelOf() would have kept them
    if (!measuringAhead.joinable())
      return;
    measuringAhead.join();
    for (std::size_t r = 0; r < ahead.size(); ++r)
      if (ahead[r] && !cancelled(options.mesh.cancel))
        state.levels.emplace(std::tuple<int, double, double>{fullKey.first, fullKey.second, ratios[r]}, *ahead[r]);
  };
  if (!done(1, 0.0))
    return Error(kLodBudgetCancelled);
  for (int i = 1; i < levels; ++i) {
    double budget = 0.0;
    if (i == 2)
      takeAhead();
    if (fullMotionMesh) {
      const double meshErrorCm = levelOf(fullKey, *fullMotionMesh, ratios[std::size_t(i - 1)]).maxErrorCm;
      budget = meshErrorCm / std::max(1.0 - motionShare, 0.05);
    } else {
      // the level's aim: the character at height / 2^i pixels, and the deviation N pixels allow there
      const double aimedSize = options.projection.viewportHeightPixels / std::pow(2.0, i);
      const double aimedDistance = distanceForScreenSize(radius, aimedSize, options.projection);
      budget = deviationForPixels(pixels, aimedDistance, radius, options.projection);
    }

    Error failed;
    double tried = 0.0;
    // the per-joint overrides of the index the level gets if kept (levels left out close up)
    const int slot = perLevel ? static_cast<int>(out.levels.size()) : 0;
    const auto motionAt = [&](double threshold) -> LevelMotion* { // computed once per (slot, E)
      const std::pair<int, double> key{slot, threshold};
      auto found = motions.find(key);
      if (found == motions.end()) {
        if (!done(i, 0.6 * std::min(1.0, tried++ / double(candidates.size())))) {
          failed = Error(kLodBudgetCancelled);
          return nullptr;
        }
        Result<LevelMotion> motion = character->motionAt(threshold, slot);
        count();
        if (report && motion)
          ++report->motionsMade;
        if (!motion) {
          failed = motion.error();
          return nullptr;
        }
        found = motions.emplace(key, std::move(motion).value()).first;
      }
      return &found->second;
    };
    // A motion whose error is a bound (E = 0's) is measured where its bound does not fit and
    // before its error is read for anything else; a bound that fits says the error does.
    const auto settled = [&](LevelMotion* motion) -> LevelMotion* {
      if (motion && !motion->motionErrorExact)
        if (Error error = character->measureMotionError(*motion)) {
          failed = error;
          return nullptr;
        }
      return motion;
    };
    const auto fits = [&](LevelMotion*& motion) {
      if (motion->motionErrorCm > motionShare * budget)
        motion = settled(motion);
      return motion && motion->motionErrorCm <= motionShare * budget;
    };
    LevelMotion* chosen = nullptr;
    double firstMiss = 0.0; // the smallest candidate above the chosen one that does not fit (0: none tried)
    for (double threshold : candidates) {
      if (threshold < previousThreshold)
        continue;
      LevelMotion* motion = motionAt(threshold);
      if (!motion)
        return failed;
      const bool fitting = fits(motion);
      if (!motion)
        return failed;
      if (fitting) {
        chosen = motion;
        firstMiss = 0.0;
      } else {
        if (firstMiss == 0.0)
          firstMiss = threshold;
        if (motion->motionErrorCm > 2.0 * budget)
          break; // errors grow with the threshold, if not strictly: this far out nothing fits
      }
    }
    if (!chosen) { // not even the previous threshold fits any more (it always did at 0)
      chosen = motionAt(previousThreshold);
      if (!chosen)
        return failed;
    }
    // A level that would repeat the previous one's motion (or keep the original's, E = 0)
    // although its budget is larger: the candidates are too coarse here, so look between the
    // chosen threshold and the first that misses, in whole cm·degrees (bisection; errors grow
    // with the threshold).
    if (chosen->threshold == previousThreshold && firstMiss > 0.0) {
      double lo = std::floor(chosen->threshold) + 1.0, hi = std::ceil(firstMiss) - 1.0; // whole E strictly between
      while (lo <= hi) {
        const double mid = std::floor(0.5 * (lo + hi));
        LevelMotion* motion = motionAt(mid);
        if (!motion)
          return failed;
        const bool fitting = fits(motion);
        if (!motion)
          return failed;
        if (fitting) {
          chosen = motion;
          lo = mid + 1.0;
        } else {
          hi = mid - 1.0;
        }
      }
    }

    chosen = settled(chosen);
    if (!chosen)
      return failed;
    if (!done(i, 0.6))
      return Error(kLodBudgetCancelled);
    LodLevel level;
    level.motionThreshold = chosen->threshold;
    level.motionErrorCm = chosen->motionErrorCm;
    level.activeJoints = chosen->bones.skeleton.jointCount();
    if (chosen->mesh) {
      const std::pair<int, double> key{slot, chosen->threshold};
      Result<MeshLod*> lod = meshFor(key, *chosen);
      if (!lod)
        return lod.error();
      const MeshFigures mesh = levelOf(key, **lod, ratios[std::size_t(i - 1)]);
      level.meshRatio = double(mesh.triangles) / double((*lod)->original().triangleCount());
      level.meshErrorCm = mesh.maxErrorCm;
      level.triangles = static_cast<int>(mesh.triangles);
    }
    const double own = distanceForPixels(level.deviationCm(), pixels, radius, options.projection);
    // A level that may switch in no farther than the one before it (coarser, yet within its
    // budget as near) leaves that one no distance of its own: the finer level goes, so that
    // switch distances rise strictly and every level is used. (Not with per-level joint
    // overrides: this level's motion was made for its own index; it is left out instead.)
    while (!perLevel && out.levels.size() > 1 && own <= out.levels.back().switchDistanceCm &&
           whyLeftOut(level, out.levels[out.levels.size() - 2], true).empty()) {
      if (report) {
        report->dropped.push_back(out.levels.back().name + " is left out: the coarser level after it switches in at " +
                                  figure(own / 100.0) + " m, no farther than its " +
                                  figure(out.levels.back().switchDistanceCm / 100.0) + " m.");
        report->simplifiedPercent.pop_back();
      }
      out.levels.pop_back();
    }
    const double previousDistance = out.levels.back().switchDistanceCm;
    if (own <= previousDistance && out.levels.size() > 1) {
      if (report)
        report->dropped.push_back("Aimed level " + std::to_string(i) + " is left out: it would switch in at " +
                                  figure(own / 100.0) + " m, no farther than " + out.levels.back().name + ".");
      continue;
    }
    const double distance = std::max(previousDistance, own);
    level.switchDistanceCm = distance;
    level.pixelError = deviationPixels(level.deviationCm(), distance, radius, options.projection);
    level.screenSizePixels = screenSizePixels(radius, distance, options.projection);
    if (keepLevel(out, level, i, true, report, chosen->simplifiedPercent))
      previousThreshold = level.motionThreshold;
  }
  progress(1.0);
  return out;
}

Result<LodSet> LodSet::fromPixelBudget(const Asset& asset, double pixels, int levels, const LodBudgetOptions& options,
                                       LodBudgetReport* report) {
  if (report)
    *report = {};
  LodBudgetOptions run = options;
  if (run.cancel)
    run.mesh.cancel = run.cancel;
  Result<LodSet> out = generateLevels(asset, pixels, levels, run, report);
  if (run.cache && !run.cache->empty())
    LodBudgetRun::state(*run.cache)->setCancel(nullptr); // the run's flag may go with it
  // note: a cancel anywhere below ends in an error of its own (kCancelled) or in levels
  // measured after it (their errors unmeasured): either way the run is the budget's cancel
  if (cancelled(run.mesh.cancel)) {
    if (report)
      *report = {};
    return Error(kLodBudgetCancelled);
  }
  return out;
}

Result<LodSet> LodSet::fromPixelBudget(const Asset& asset, double pixels, int levels) {
  const LodBudgetOptions options;
  return fromPixelBudget(asset, pixels, levels, options);
}

Error LodSet::validate() const {
  if (Error error = projection.validate())
    return error;
  if (levels.empty())
    return Error("LOD set: no level");
  const LodLevel& first = levels.front();
  if (first.motionThreshold != 0.0 || first.meshRatio != 1.0 || first.switchDistanceCm != 0.0)
    return Error("LOD set: level 0 is the original (threshold 0, ratio 1, distance 0)");
  if (!std::isfinite(boundingRadiusCm) || boundingRadiusCm < 0.0)
    return Error("LOD set: the bounding radius must be finite and >= 0 cm");
  std::set<std::string> names;
  double previous = 0.0;
  for (std::size_t i = 0; i < levels.size(); ++i) {
    const LodLevel& level = levels[i];
    const std::string what = "LOD set: level " + std::to_string(i);
    if (level.name.size() > kMaxLevelNameBytes)
      return Error(what + ": the name is " + std::to_string(level.name.size()) +
                   " bytes long; a level name has at most " + std::to_string(kMaxLevelNameBytes));
    if (!names.insert(level.name).second)
      return Error(what + ": the name '" + level.name + "' is used twice");
    if (Error error = validateThreshold(level.motionThreshold, what + " threshold"))
      return error;
    if (!(level.meshRatio > 0.0 && level.meshRatio <= 1.0))
      return Error(what + ": the mesh ratio must be in (0, 1]");
    if (!std::isfinite(level.switchDistanceCm) || level.switchDistanceCm < previous)
      return Error(what + ": switch distances must be finite and never fall from one level to the next");
    if (!std::isfinite(level.pixelError) || level.pixelError < 0.0 || !std::isfinite(level.screenSizePixels) ||
        level.screenSizePixels < 0.0)
      return Error(what + ": pixel figures must be finite and >= 0");
    previous = level.switchDistanceCm;
  }
  return {};
}

} // namespace mlod
