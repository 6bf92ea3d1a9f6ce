#pragma once
// Brute-force references for JPC, straight from the definitions of docs/architecture.md section 4,
// for clips of a few hundred frames: the full n x n table (test-only, never in core),
// STEPs 1-6 as written, and an O(n^3) optimal partition. They call the same scalar error
// kernel (JointTrack::error) as the banded code, so results must agree exactly.

#include "core/jpc/cluster_set.h"
#include "core/jpc/posture_error.h"

#include <vector>

namespace mlod::test {

// table[ref * n + t] = E(t, ref) for every pair.
std::vector<double> fullTable(const JointTrack& track);
// STEP 1 from the full table: the last frame of row ref's run after the diagonal, and the
// first frame of its run before it.
std::vector<int> referenceRowEnds(const std::vector<double>& table, int n, double threshold);
std::vector<int> referenceRowStarts(const std::vector<double>& table, int n, double threshold);
// STEPs 2-5 as the paper's loop: find the longest range (earliest on ties), take it, cut
// or drop every range overlapping it, drop ranges shorter than 3.
std::vector<FrameRange> referenceGreedyRanges(std::vector<int> rowEnds);
// Eq. (7) over every row of the range: the feasible row with the least sum (ascending t),
// earliest on ties; -1 when no row is feasible.
int referenceKey(const std::vector<double>& table, int n, FrameRange range, double threshold);
// The most frames a valid partition can cover, and the fewest clusters doing so.
struct Coverage {
  int frames = 0;
  int clusters = 0;
};
Coverage referenceOptimalCoverage(const std::vector<double>& table, int n, double threshold);

} // namespace mlod::test
