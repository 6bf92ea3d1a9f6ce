#pragma once
// Key posture of a cluster (Ahn & Wohn, section 4.3, eq. (7); STEP 6), restricted as
// docs/architecture.md section 4 says: among the rows k of the cluster whose errors to every frame
// of the cluster stay within the threshold, the one with the least sum of errors
// sum_t E(t, k), summed in ascending t; ties: the earliest k. So E(t, key) <= T holds for
// every frame of the cluster.

#include "core/jpc/cluster_set.h"
#include "core/jpc/clustering_table.h"
#include "core/jpc/posture_error.h"
#include "core/jpc/work_budget.h"

#include <cstdint>

namespace mlod {

struct KeyPosture {
  int key = -1;                 // frame; -1 when no row of the range is within the threshold
  double errorSum = 0.0;        // sum_t E(t, key) over the range, cm·degrees
  double maxError = 0.0;        // max_t E(t, key) over the range, cm·degrees
  std::int64_t evaluations = 0; // exact error evaluations spent (statistic)
  std::int64_t work = 0;        // JpcWorkBudget units spent: exact and float evaluations
  bool stopped = false;         // the budget ran out: key is -1
};

// `table` (optional, built for the same threshold) rules out rows whose run cannot hold
// the range without evaluating them. `budget` (optional) is charged as the search goes;
// once it is past its limit the search stops with `stopped` set and no key.
//
// note: eq. (7) is m^2 evaluations for a cluster of m frames. Exactly the same key comes
// out of far fewer: rows of identical postures have identical sums (only the first can
// win), and with one pivot row p evaluated, the triangle inequality gives every row k the
// lower bound sum_t |E(t, p) - E(k, p)| (sorted prefix sums, O(log m) per row); rows are
// tried by increasing bound and dropped once the bound passes the best sum so far. Long
// clusters add 8 landmark rows (farthest-first) for the per-frame bound
// sum_t max_p |E(t, p) - E(k, p)|, which drops most of the rest. The rows left are summed
// with the float SIMD kernel (JointTrack::approximateErrors), which
// brackets each exact sum within m x its error bound; only rows whose bracket still
// reaches the best one are summed exactly (ascending t, as eq. (7) says). Every margin
// covers rounding, so the key is the one the full table would give.
KeyPosture keyPosture(const JointTrack& track, FrameRange range, double threshold,
                      const ClusteringTable* table = nullptr, JpcWorkBudget* budget = nullptr);

} // namespace mlod
