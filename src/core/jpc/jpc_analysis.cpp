#include "core/jpc/jpc_analysis.h"

#include "core/jpc/parallel_for.h"
#include "core/jpc/simplified_motion.h"

#include <cassert>

namespace mlod {

namespace {
// What decides one joint's clustering besides the clip: equal keys give equal clusters.
struct PairKey {
  bool active = false; // clusterable and not locked
  double threshold = 0.0;
  double alpha = 0.0;
  JpcMode mode = JpcMode::Greedy;
  bool operator==(const PairKey&) const = default;
};

PairKey keyOf(const JpcClip& prepared, int joint, int level, double levelThreshold) {
  PairKey key;
  key.active = prepared.clusterable(joint) && !prepared.locked(joint);
  if (!key.active)
    return key;
  key.threshold = prepared.threshold(joint, level, levelThreshold);
  key.alpha = prepared.settings().alphaFor(prepared.jointName(joint));
  key.mode = prepared.settings().mode;
  return key;
}

// The joint's error track is the same in both (so is every clustering at an equal key).
bool tracksMatch(const JpcSettings& a, const JpcSettings& b, const std::string& joint) {
  return a.alphaFor(joint) == b.alphaFor(joint) && a.lockedFor(joint) == b.lockedFor(joint) &&
         a.zeroLength == b.zeroLength;
}

bool cancelled(const JpcAnalysisOptions& options) {
  return options.cancel && options.cancel->load();
}
} // namespace

bool JpcAnalysis::answers(const JpcAnalysisRequest& request) const {
  return asset == request.asset && clip == request.clip && levelThresholds == request.levelThresholds &&
         settings.alpha == request.settings.alpha && settings.mode == request.settings.mode &&
         settings.zeroLength == request.settings.zeroLength && settings.joints == request.settings.joints;
}

Result<std::shared_ptr<const JpcAnalysis>> buildJpcAnalysis(const JpcAnalysisRequest& request,
                                                            std::shared_ptr<const JpcAnalysis> previous,
                                                            const JpcAnalysisOptions& options) {
  assert(request.asset && request.clip >= 0 && request.clip < static_cast<int>(request.asset->clips.size()));
  const Asset& asset = *request.asset;
  const Clip& clip = asset.clips[static_cast<std::size_t>(request.clip)];
  if (previous && (previous->asset != request.asset || previous->clip != request.clip))
    previous.reset();
  for (std::size_t level = 0; level < request.levelThresholds.size(); ++level)
    if (Error error =
            validateThreshold(request.levelThresholds[level], "level " + std::to_string(level) + " threshold"))
      return error;

  auto out = std::make_shared<JpcAnalysis>();
  out->asset = request.asset;
  out->clip = request.clip;
  out->settings = request.settings;
  out->levelThresholds = request.levelThresholds;
  // Preparing builds every joint's error track: cheap next to clustering, and simpler than
  // patching one joint's track after an alpha edit.
  Result<JpcClip> prepared = JpcClip::prepare(asset.skeleton, clip, request.settings);
  if (!prepared)
    return prepared.error();
  out->prepared = std::make_shared<const JpcClip>(std::move(prepared).value());
  const JpcClip& jpc = *out->prepared;
  out->originalPositions = previous
                               ? previous->originalPositions
                               : std::make_shared<const std::vector<glm::vec3>>(jointPositions(asset.skeleton, clip));

  // Which (level, joint) pairs need clustering, and which previous clustering serves the rest.
  const int levels = static_cast<int>(request.levelThresholds.size());
  const int joints = jpc.jointCount();
  out->clusterings.assign(static_cast<std::size_t>(levels),
                          std::vector<JointClustering>(static_cast<std::size_t>(joints)));
  std::vector<int> todo;
  std::vector<bool> levelChanged(static_cast<std::size_t>(levels), true);
  for (int level = 0; level < levels; ++level) {
    const double levelThreshold = request.levelThresholds[static_cast<std::size_t>(level)];
    bool same = previous && level < previous->levelCount() &&
                previous->levelThresholds[static_cast<std::size_t>(level)] == levelThreshold;
    for (int joint = 0; joint < joints; ++joint) {
      const PairKey key = keyOf(jpc, joint, level, levelThreshold);
      const bool trackSame = previous && tracksMatch(previous->settings, request.settings, jpc.jointName(joint));
      if (same)
        same = trackSame && keyOf(*previous->prepared, joint, level,
                                  previous->levelThresholds[static_cast<std::size_t>(level)]) == key;
      if (!key.active || level == 0) // level 0 is the original: nothing clustered
        continue;
      bool reused = false;
      // the same level first (nothing changed there), then any other
      for (int k = 0; previous && trackSame && k < previous->levelCount() && !reused; ++k) {
        const int old = k == 0 ? level : (k == level ? 0 : k);
        if (old < 1 || old >= previous->levelCount())
          continue;
        if (keyOf(*previous->prepared, joint, old, previous->levelThresholds[static_cast<std::size_t>(old)]) == key) {
          out->clusterings[static_cast<std::size_t>(level)][static_cast<std::size_t>(joint)] =
              previous->clusterings[static_cast<std::size_t>(old)][static_cast<std::size_t>(joint)];
          reused = true;
          out->reusedFromOtherLevels += old != level ? 1 : 0;
        }
      }
      if (!reused)
        todo.push_back(level * joints + joint);
    }
    levelChanged[static_cast<std::size_t>(level)] = !same;
  }
  out->clusteredPairs = static_cast<int>(todo.size());
  const int total = static_cast<int>(todo.size()) + levels;
  std::atomic<int> done{0};
  parallelFor(static_cast<int>(todo.size()), options.threads, [&](int i) {
    if (cancelled(options))
      return;
    const int task = todo[static_cast<std::size_t>(i)];
    const int level = task / joints, joint = task % joints;
    out->clusterings[static_cast<std::size_t>(level)][static_cast<std::size_t>(joint)] =
        jpc.clusterJoint(joint, level, request.levelThresholds[static_cast<std::size_t>(level)]);
    if (options.progress)
      options.progress(++done, total);
  });
  if (cancelled(options))
    return Error(kJpcAnalysisCancelled);

  out->levels.resize(static_cast<std::size_t>(levels));
  parallelFor(levels, options.threads, [&](int level) {
    if (cancelled(options))
      return;
    const std::size_t l = static_cast<std::size_t>(level);
    if (!levelChanged[l])
      out->levels[l] = previous->levels[l];
    else
      out->levels[l] = measureLevel(jpc, asset.skeleton, clip, level, request.levelThresholds[l], out->clusterings[l],
                                    *out->originalPositions);
    if (options.progress)
      options.progress(++done, total);
  });
  if (cancelled(options))
    return Error(kJpcAnalysisCancelled);
  return std::shared_ptr<const JpcAnalysis>(std::move(out));
}

} // namespace mlod
