#include "editor/document/analysis.h"

#include "core/jpc/simplified_motion.h"

#include <QtConcurrent/QtConcurrentMap>

#include <numeric>

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

bool tracksMatch(const JpcSettings& a, const JpcSettings& b, const std::string& joint) {
  return a.alphaFor(joint) == b.alphaFor(joint) && a.lockedFor(joint) == b.lockedFor(joint) &&
         a.zeroLength == b.zeroLength;
}
} // namespace

std::shared_ptr<const Analysis> buildAnalysis(const AnalysisRequest& request, std::shared_ptr<const Analysis> previous,
                                              const std::atomic<bool>& cancel,
                                              const std::function<void(int, int)>& progress, std::string& out_error) {
  assert(request.asset && request.clip >= 0 && request.clip < static_cast<int>(request.asset->clips.size()));
  const Asset& asset = *request.asset;
  const Clip& clip = asset.clips[static_cast<std::size_t>(request.clip)];
  if (previous && (previous->asset != request.asset || previous->clip != request.clip))
    previous.reset();
  for (std::size_t level = 0; level < request.levelThresholds.size(); ++level)
    if (Error error = validateThreshold(request.levelThresholds[level], "level " + std::to_string(level) + " threshold")) {
      out_error = error.message();
      return nullptr;
    }

  auto out = std::make_shared<Analysis>();
  out->asset = request.asset;
  out->clip = request.clip;
  out->settings = request.settings;
  out->levelThresholds = request.levelThresholds;
  // Preparing builds every joint's error track: cheap next to clustering, and simpler than
  // patching one joint's track after an alpha edit.
  Result<JpcClip> prepared = JpcClip::prepare(asset.skeleton, clip, request.settings);
  if (!prepared) {
    out_error = prepared.message();
    return nullptr;
  }
  out->prepared = std::make_shared<const JpcClip>(std::move(prepared).value());
  const JpcClip& jpc = *out->prepared;
  out->originalPositions = previous ? previous->originalPositions
                                    : std::make_shared<const std::vector<glm::vec3>>(jointPositions(asset.skeleton, clip));

  // Which (level, joint) pairs need clustering, and which previous clustering serves the rest.
  const int levels = static_cast<int>(request.levelThresholds.size());
  const int joints = jpc.jointCount();
  out->clusterings.assign(static_cast<std::size_t>(levels), std::vector<JointClustering>(static_cast<std::size_t>(joints)));
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
      for (int old = 1; previous && trackSame && old < previous->levelCount() && !reused; ++old)
        if (keyOf(*previous->prepared, joint, old, previous->levelThresholds[static_cast<std::size_t>(old)]) == key) {
          out->clusterings[static_cast<std::size_t>(level)][static_cast<std::size_t>(joint)] =
              previous->clusterings[static_cast<std::size_t>(old)][static_cast<std::size_t>(joint)];
          reused = true;
        }
      if (!reused)
        todo.push_back(level * joints + joint);
    }
    levelChanged[static_cast<std::size_t>(level)] = !same;
  }
  out->clusteredPairs = static_cast<int>(todo.size());
  const int total = static_cast<int>(todo.size()) + levels;
  std::atomic<int> done{0};
  // Off the caller's thread already; spread the pairs over the global pool.
  QtConcurrent::blockingMap(todo, [&](int task) {
    if (cancel.load())
      return;
    const int level = task / joints, joint = task % joints;
    out->clusterings[static_cast<std::size_t>(level)][static_cast<std::size_t>(joint)] =
        jpc.clusterJoint(joint, level, request.levelThresholds[static_cast<std::size_t>(level)]);
    if (progress)
      progress(++done, total);
  });
  if (cancel.load())
    return nullptr;

  out->levels.resize(static_cast<std::size_t>(levels));
  std::vector<int> levelIndices(static_cast<std::size_t>(levels));
  std::iota(levelIndices.begin(), levelIndices.end(), 0);
  QtConcurrent::blockingMap(levelIndices, [&](int level) {
    if (cancel.load())
      return;
    const std::size_t l = static_cast<std::size_t>(level);
    if (!levelChanged[l]) {
      out->levels[l] = previous->levels[l];
    } else {
      out->levels[l] = measureLevel(jpc, asset.skeleton, clip, level, request.levelThresholds[l], out->clusterings[l],
                                    *out->originalPositions);
    }
    if (progress)
      progress(++done, total);
  });
  if (cancel.load())
    return nullptr;
  return out;
}

} // namespace mlod
