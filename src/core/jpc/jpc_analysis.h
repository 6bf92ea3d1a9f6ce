#pragma once
// The JPC figures of one clip at every level of a LOD set, as one immutable snapshot, rebuilt
// incrementally after each edit (docs/architecture.md section 4, "Incremental analysis"): only
// the (level, joint) pairs whose inputs changed since the previous snapshot are clustered
// again, so an edit of one joint's threshold re-clusters one joint at one level, and a level
// whose clusters all stayed keeps its measured figures. The studio runs it after every edit,
// off its UI thread; it needs no Qt.
//
// What decides a (level, joint) clustering, and so keys the cache: the clip (the asset and
// clip index), and for the joint: whether it is clustered at all (clusterable and not
// locked), its threshold at that level T_j, its alpha_j, the mode, and the zero-length
// tolerance. A pair whose key matches the previous snapshot's pair at *any* level reuses that
// clustering (adding a level at an existing threshold clusters nothing).
//
// Levels are the LodSet's: level 0 is the original (nothing clustered, zero error); level
// i >= 1 clusters at its threshold with the per-joint overrides of level i.
//
// Units: thresholds and errors in cm·degrees, positions in cm.

#include "core/asset.h"
#include "core/error.h"
#include "core/jpc/jpc.h"

#include <atomic>
#include <functional>
#include <glm/glm.hpp>
#include <memory>
#include <string>
#include <vector>

namespace mlod {

struct JpcAnalysisRequest {
  std::shared_ptr<const Asset> asset; // not null
  int clip = 0;                       // an index into asset->clips
  JpcSettings settings;
  std::vector<double> levelThresholds; // per level, cm·degrees (level 0's is 0)
};

struct JpcAnalysis {
  std::shared_ptr<const Asset> asset;
  int clip = 0;
  JpcSettings settings;
  std::vector<double> levelThresholds;
  std::shared_ptr<const JpcClip> prepared;
  std::shared_ptr<const std::vector<glm::vec3>> originalPositions; // jointPositions() of the clip
  std::vector<std::vector<JointClustering>> clusterings;           // [level][joint]
  std::vector<JpcLevelResult> levels;                              // per level, measured
  int clusteredPairs = 0; // (level, joint) pairs clustered for this snapshot (the rest were reused)
  // Pairs whose clustering came from another level of the previous snapshot (a level moved,
  // a threshold set to another level's): new figures that needed no clustering.
  int reusedFromOtherLevels = 0;

  const Clip& clipRef() const { return asset->clips[static_cast<std::size_t>(clip)]; }
  int levelCount() const { return static_cast<int>(levels.size()); }
  // True when this snapshot already holds the figures `request` asks for (same asset, clip,
  // thresholds and settings): nothing to run.
  bool answers(const JpcAnalysisRequest& request) const;
};

struct JpcAnalysisOptions {
  int threads = 0; // worker threads for the clustering (0 = one per hardware thread); the result does not depend on it
  // Raised from any thread to stop early; may be null.
  const std::atomic<bool>* cancel = nullptr;
  // progress(done, total), called from the worker threads (under no lock); may be empty.
  std::function<void(int done, int total)> progress;
};

inline constexpr const char* kJpcAnalysisCancelled = "cancelled";

// Builds the snapshot for `request`, reusing from `previous` (may be null; ignored when it is
// of another asset or clip) every clustering and level whose key is unchanged. The result is
// never null. Errors: kJpcAnalysisCancelled when options.cancel was raised before the end;
// settings or thresholds that do not validate; a clip JPC cannot prepare.
Result<std::shared_ptr<const JpcAnalysis>> buildJpcAnalysis(const JpcAnalysisRequest& request,
                                                            std::shared_ptr<const JpcAnalysis> previous,
                                                            const JpcAnalysisOptions& options = {});

} // namespace mlod
