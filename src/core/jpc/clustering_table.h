#pragma once
// The clustering table of one joint (Ahn & Wohn, section 4.2, Figure 5; STEP 1), without
// the n x n storage: what clustering needs from row `ref` is the run of frames around the
// diagonal whose error to `ref` stays within the threshold T, so the table keeps, per row,
// the end of the run after the diagonal (the paper's "available range", upper triangle)
// and, on request, its start before the diagonal (the optimal mode's key windows). Any
// entry is available on demand through entry(). Memory: 8 bytes per frame for the step
// bound below, plus 4 for the ends and 4 for the starts.
//
// note: the runs are exact, entry for entry as a full table would give them, but most
// entries are never evaluated. E is a pseudometric (posture_error.h), so with the
// frame-to-frame errors s(u) = E(u, u - 1) summed into a prefix,
//   E(t, ref) <= E(a, ref) + sum of s(u) for u in (a, t]
// for any evaluated anchor a; every frame whose bound stays within T (less a margin for
// rounding) joins the run unevaluated. Frames identical to their predecessor (still
// joints: CMU fingers, LHipJoint) have the predecessor's error bit for bit and are
// skipped even at T = 0. This is the paper's long-clip reduction by angular speed
// (section 4.3, E_pos(t, t - 1)), made exact. The frames the bound leaves open go through
// the float SIMD kernel (JointTrack::approximateErrors) in blocks; only those within its
// error bound of T are evaluated exactly.

#include "core/jpc/posture_error.h"

#include <cstdint>
#include <vector>

namespace mlod {

// Which runs a table finds.
enum class TableRows {
  EndsOnDemand,  // each row's end when first asked for (the greedy STEPs need few at large T)
  Ends,          // every row's end
  EndsAndStarts, // every row's end and start (the optimal mode)
};

class ClusteringTable {
public:
  ClusteringTable() = default;
  // The runs of the rows of `track` (which must outlive the table) for threshold
  // `threshold` (cm·degrees, >= 0). A threshold at or above track.maxError() makes every
  // run the whole clip with no evaluation.
  ClusteringTable(const JointTrack& track, double threshold, TableRows rows);
  ClusteringTable(const JointTrack& track, double threshold, bool withStarts)
      : ClusteringTable(track, threshold, withStarts ? TableRows::EndsAndStarts : TableRows::Ends) {}

  int frameCount() const { return static_cast<int>(m_ends.size()); }
  double threshold() const { return m_threshold; }
  bool hasStarts() const { return !m_starts.empty(); }
  bool wholeClip() const { return m_wholeClip; }

  // The last frame e of the longest run [ref, e] with E(t, ref) <= T for all t in it.
  // With EndsOnDemand the first call for a row computes it: such a table is not for
  // sharing between threads.
  int rowEnd(int ref) const {
    int& end = m_ends[static_cast<std::size_t>(ref)];
    if (end < 0)
      end = computeRowEnd(ref);
    return end;
  }
  // rowEnd(ref) when already known, else -1 (never computes).
  int knownRowEnd(int ref) const { return m_ends[static_cast<std::size_t>(ref)]; }
  // The first frame s of the longest run [s, ref] with E(t, ref) <= T. Needs EndsAndStarts.
  int rowStart(int ref) const { return m_starts[static_cast<std::size_t>(ref)]; }
  // Every row's end (-1 for rows not computed yet with EndsOnDemand).
  const std::vector<int>& rowEnds() const { return m_ends; }
  const std::vector<int>& rowStarts() const { return m_starts; } // empty without EndsAndStarts

  // Table entry E(t, ref), evaluated on demand (the same kernel the runs came from).
  double entry(int t, int ref) const { return m_track->error(t, ref); }

  // Exact error evaluations spent building the runs (a statistic for benchmarks and tests).
  std::int64_t evaluations() const { return m_evaluations; }

  // Frame-to-frame errors, each rounded up to a multiple of a power-of-two quantum and
  // summed exactly in 64-bit integers: prefix[t] * quantum >= the sum of s(u) for u in
  // (0, t], with no rounding that grows with the clip's length.
  struct StepBound {
    std::vector<std::uint64_t> prefix;        // per frame
    double quantum = 1.0;                     // cm·degrees per unit of prefix
    double slack = 0.0;                       // margin kept below T (cm·degrees)
    bool usable = false;                      // false at T within the margin (T = 0 above all)
    std::uint64_t units(double budget) const; // units of prefix that fit in `budget`; saturates
  };

private:
  int computeRowEnd(int ref) const;

  const JointTrack* m_track = nullptr;
  double m_threshold = 0.0;
  bool m_wholeClip = false;
  StepBound m_bound;
  mutable std::vector<int> m_ends;
  std::vector<int> m_starts;
  mutable std::int64_t m_evaluations = 0;
};

// The largest absolute rounding error of one JointTrack::error() value against the exact
// pseudometric, generously bounded (cm·degrees). The pruning in clustering and key
// postures keeps this margin so that it never changes a result.
double errorRoundingBound(const JointTrack& track);

} // namespace mlod
