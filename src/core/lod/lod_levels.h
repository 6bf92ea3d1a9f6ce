#pragma once
// Edits of a LOD set's level list as an author makes them (docs/architecture.md sections 3
// and 7), and the rules they keep. The editor's LOD Levels dock, a script or a test call
// these; each returns the set after the edit or the reason it is refused, and never changes
// its input.
//
// The rules:
// - Level 0 is the original: threshold 0, mesh ratio 1, switch distance 0. It can be renamed,
//   never removed, moved or given another threshold, ratio or distance.
// - A new level goes last, named "LOD<n>" (n = the number of levels, or the first larger n
//   whose name is free), with the last level's mesh ratio and switch distance.
// - Names are non-empty (surrounding blanks dropped), unique and at most kMaxLevelNameBytes long.
// - Thresholds are finite and >= 0 (validateThreshold()), mesh ratios in (0, 1].
// - Switch distances belong to the positions, so they stay non-decreasing: moving a level
//   keeps the distance column as it was, and a level's distance is at least the previous
//   level's; later levels nearer than a new distance move out to it in the same edit.
//
// Per-joint threshold overrides are indexed by level; `order` says where each level of the
// result came from so they can follow their level (remapLevels(), core/project.h).
//
// Units: thresholds in cm·degrees, distances in cm.

#include "core/error.h"
#include "core/jpc/jpc_settings.h"
#include "core/lod/lod_set.h"

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mlod {

struct LodSetEdit {
  LodSet lods;            // the set after the edit
  std::vector<int> order; // order[i]: the index before the edit of level i, -1 for a new level
};

// "LOD<n>" for the next level of `lods`: n = the level count, or the first larger n free.
std::string nextLodLevelName(const LodSet& lods);
// The threshold the editor offers for a new level: twice the last level's, 5 after the
// original alone (the paper's smallest Table 1 threshold).
double nextLodLevelThreshold(const LodSet& lods);

// Appends a level at `threshold`. Errors: a threshold that does not validate.
Result<LodSetEdit> addLodLevel(const LodSet& lods, double threshold);
// Errors: level 0 or out of range.
Result<LodSetEdit> removeLodLevel(const LodSet& lods, int level);
// Moves level `from` to position `to` (both >= 1); switch distances stay with the positions.
// Errors: level 0, out of range, from == to.
Result<LodSetEdit> moveLodLevel(const LodSet& lods, int from, int to);

// In-place edits (order is the identity). Errors: out of range, level 0 (except a rename),
// and the value rules above.
Result<LodSetEdit> setLodLevelThreshold(const LodSet& lods, int level, double threshold);
Result<LodSetEdit> renameLodLevel(const LodSet& lods, int level, std::string_view name);
Result<LodSetEdit> setLodLevelMeshRatio(const LodSet& lods, int level, double ratio);
Result<LodSetEdit> setLodLevelSwitchDistance(const LodSet& lods, int level, double cm);

// The pixel budget the set's switch distances were generated for (LodSet::fromPixelBudget()),
// to generate them again from the same budget (after a new unit made them stale): the pixel
// error of the first level with a switch distance, 1 px where that level stores none (a set
// from before pixel errors were kept); none when no level has a switch distance yet.
std::optional<double> switchDistancePixelBudget(const LodSet& lods);

// `generated` replacing `before` (LodSet::fromPixelBudget()): level i keeps level i's
// overrides where `before` had a level i.
LodSetEdit replaceLodLevels(const LodSet& before, LodSet generated);

// A per-joint threshold override above the threshold of the level it belongs to: the
// author's choice, kept by replaceLodLevels(), but a joint that strays further than its
// level's budget allowed; the Budget dialog lists each so none stays unseen.
struct LodOverrideAbove {
  std::string joint;
  int level = 0;
  double overrideThreshold = 0.0; // cm·degrees
  double levelThreshold = 0.0;    // cm·degrees; 0 where `beyond`
  std::string asset = {};         // the file name of the asset whose joint it is; empty where not told
  bool beyond = false;            // at a level the set has not: replaceLodLevels() drops it
  friend bool operator==(const LodOverrideAbove&, const LodOverrideAbove&) = default;
};
// Every override of `settings` at a level of `lods` above that level's threshold, by level
// then joint name.
std::vector<LodOverrideAbove> overridesAboveLevels(const JpcSettings& settings, const LodSet& lods);

} // namespace mlod
