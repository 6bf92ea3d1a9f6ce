#pragma once
// The JPC figures of the clip in view, as one immutable snapshot the views read. Built off
// the UI thread from the core (JpcClip, measureLevel); only the (level, joint) pairs whose
// inputs changed since the previous snapshot are clustered again, so an edit of one joint's
// threshold re-clusters one joint at one level. Levels are the project's LodSet levels:
// level 0 is the original (nothing clustered, zero error), level i >= 1 clusters at its
// threshold with the per-joint overrides of level i.

#include "core/asset.h"
#include "core/jpc/jpc.h"

#include <atomic>
#include <functional>
#include <memory>
#include <vector>

namespace mlod {

struct Analysis {
  std::shared_ptr<const Asset> asset;
  int clip = 0;
  JpcSettings settings;
  std::vector<double> levelThresholds;
  std::shared_ptr<const JpcClip> prepared;
  std::shared_ptr<const std::vector<glm::vec3>> originalPositions; // jointPositions() of the clip
  std::vector<std::vector<JointClustering>> clusterings;           // [level][joint]
  std::vector<JpcLevelResult> levels;                              // per level, measured
  int clusteredPairs = 0; // (level, joint) pairs clustered for this snapshot (the rest were reused)

  const Clip& clipRef() const { return asset->clips[static_cast<std::size_t>(clip)]; }
  int levelCount() const { return static_cast<int>(levels.size()); }
};

struct AnalysisRequest {
  std::shared_ptr<const Asset> asset;
  int clip = 0;
  JpcSettings settings;
  std::vector<double> levelThresholds;
};

// Builds the snapshot for `request`, reusing from `previous` (may be null) every joint
// clustering whose inputs (the clip, T_j, alpha_j, lock, mode) are unchanged. Returns null
// when `cancel` was raised before the end, or with `out_error` set when the settings do not
// validate. `progress(done, total)` is called from the worker.
std::shared_ptr<const Analysis> buildAnalysis(const AnalysisRequest& request, std::shared_ptr<const Analysis> previous,
                                              const std::atomic<bool>& cancel,
                                              const std::function<void(int, int)>& progress, std::string& out_error);

} // namespace mlod
