#pragma once
// Optimal cluster selection (docs/architecture.md section 4, beyond the paper): under the same error
// bound as the greedy STEPs, the disjoint ranges of >= kMinClusterFrames frames, each with
// some key k inside whose error to every frame of the range is within the threshold, that
// cover the most frames; among those, the fewest ranges.

#include "core/jpc/cluster_set.h"

#include <span>
#include <vector>

namespace mlod {

// Row k's feasible window is [rowStarts[k], rowEnds[k]] (ClusteringTable with starts):
// the longest run around k within the threshold of k. A range [a, b] can be a cluster
// keyed at k exactly when rowStarts[k] <= a <= k <= b <= rowEnds[k].
//
// note: keeping, for each range end, only the smallest feasible start is not exact (a
// later start can leave room for a better cluster before it). The dynamic program here
// keeps for each key the best start of its whole window, so it is exact:
// O(n log n) time, O(n) memory. Returns the ranges sorted by first frame; the keys are
// chosen afterwards (key_posture.h).
std::vector<FrameRange> optimalRanges(std::span<const int> rowStarts, std::span<const int> rowEnds);

} // namespace mlod
