// Clustering table, Ahn & Wohn section 4.2 (STEP 1), banded; docs/architecture.md section 4.
#include "core/jpc/clustering_table.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace mlod {

double errorRoundingBound(const JointTrack& track) {
  // note: one evaluation is within a few ulps of 180 * (r + alpha) of the exact angle sum
  // (atan2 of well-conditioned arguments, double throughout); 1e-12 relative is ~5000 ulps.
  return 1e-12 * track.maxError() + std::numeric_limits<double>::min();
}

namespace {
using StepBound = ClusteringTable::StepBound;

StepBound buildStepBound(const JointTrack& track, double threshold, std::int64_t& evaluations) {
  StepBound bound;
  const int n = track.frameCount();
  const double eta = errorRoundingBound(track);
  bound.slack = 3.0 * eta + 8.0 * std::numeric_limits<double>::epsilon() * (threshold + track.maxError());
  bound.usable = threshold > bound.slack;
  if (!bound.usable || n < 2)
    return bound;
  // 2^61 units in all leave headroom for the additions below.
  const double total = static_cast<double>(n) * (track.maxError() + eta) * 1.01;
  bound.quantum = std::ldexp(1.0, std::ilogb(total) - 60);
  bound.prefix.assign(static_cast<std::size_t>(n), 0);
  for (int t = 1; t < n; ++t) {
    std::uint64_t step = 0;
    if (!track.sameAsPrevious(t)) {
      // the true step is at most the computed one plus eta
      step = static_cast<std::uint64_t>(std::ceil((track.error(t, t - 1) + eta) / bound.quantum));
      ++evaluations;
    }
    bound.prefix[static_cast<std::size_t>(t)] = bound.prefix[static_cast<std::size_t>(t - 1)] + step;
  }
  return bound;
}

// Blocks of the approximate kernel grow from kFirstBlock to kLastBlock frames while a run
// goes on: most runs end within a few frames of where the bound gives out.
constexpr int kFirstBlock = 8;
constexpr int kLastBlock = 64;

// Frame by frame from the diagonal, each frame is decided by the first of:
// - it holds the same rotation as its neighbour inside the run: the same error, exactly;
// - the triangle bound from the last anchor a (a frame whose error is known to within
//   its upper bound u):
//     computed E(t, ref) <= exact E(t, ref) + eta <= exact E(a, ref) + exact steps + eta
//                        <= u + (prefix[t] - prefix[a]) * quantum + 2 eta,
//   slack covering 2 eta and the rounding of the budget;
// - the approximate kernel, when it is more than its bound away from T;
// - the exact kernel.
int scanForward(const JointTrack& track, const StepBound& bound, double threshold, int ref, std::int64_t& evaluations) {
  const int n = track.frameCount();
  const double delta = track.approximationBound();
  float approximate[kLastBlock];
  int block = kFirstBlock;
  int last = ref; // every frame in [ref, last] is within the threshold
  int anchor = ref;
  double anchorUpper = 0.0;
  while (last + 1 < n) {
    const int t = last + 1;
    if (track.sameAsPrevious(t)) {
      last = track.runLast(t);
      continue;
    }
    if (bound.usable) {
      const double budget = threshold - bound.slack - anchorUpper;
      if (budget >= 0.0) {
        const std::uint64_t limit = bound.prefix[static_cast<std::size_t>(anchor)] + bound.units(budget);
        if (bound.prefix[static_cast<std::size_t>(t)] <= limit) {
          const auto begin = bound.prefix.begin() + t;
          last = static_cast<int>(std::upper_bound(begin, bound.prefix.end(), limit) - bound.prefix.begin()) - 1;
          continue;
        }
      }
    }
    const int count = std::min(block, n - t);
    block = std::min(2 * block, kLastBlock);
    track.approximateErrors(ref, t, count, approximate);
    for (int i = 0; i < count; ++i) {
      const int u = t + i;
      const double estimate = approximate[i];
      double upper = estimate + delta;
      if (!(upper <= threshold)) {
        if (estimate - delta > threshold)
          return last;
        upper = track.error(u, ref);
        ++evaluations;
        if (!(upper <= threshold))
          return last;
      }
      anchor = u;
      anchorUpper = upper;
      last = u;
    }
  }
  return last;
}

int scanBackward(const JointTrack& track, const StepBound& bound, double threshold, int ref,
                 std::int64_t& evaluations) {
  const double delta = track.approximationBound();
  float approximate[kLastBlock];
  int block = kFirstBlock;
  int first = ref; // every frame in [first, ref] is within the threshold
  int anchor = ref;
  double anchorUpper = 0.0;
  while (first > 0) {
    const int t = first - 1;
    if (track.sameAsPrevious(first)) { // t holds the same rotation as `first`
      first = track.runFirst(t);
      continue;
    }
    if (bound.usable) {
      const double budget = threshold - bound.slack - anchorUpper;
      if (budget >= 0.0) {
        const std::uint64_t top = bound.prefix[static_cast<std::size_t>(anchor)];
        const std::uint64_t units = bound.units(budget);
        const std::uint64_t floorValue = units >= top ? 0 : top - units;
        if (bound.prefix[static_cast<std::size_t>(t)] >= floorValue) {
          first = static_cast<int>(std::lower_bound(bound.prefix.begin(), bound.prefix.begin() + t + 1, floorValue) -
                                   bound.prefix.begin());
          continue;
        }
      }
    }
    const int count = std::min(block, t + 1);
    block = std::min(2 * block, kLastBlock);
    track.approximateErrors(ref, t - count + 1, count, approximate);
    for (int i = count - 1; i >= 0; --i) {
      const int u = t - count + 1 + i;
      const double estimate = approximate[i];
      double upper = estimate + delta;
      if (!(upper <= threshold)) {
        if (estimate - delta > threshold)
          return first;
        upper = track.error(u, ref);
        ++evaluations;
        if (!(upper <= threshold))
          return first;
      }
      anchor = u;
      anchorUpper = upper;
      first = u;
    }
  }
  return first;
}
} // namespace

std::uint64_t ClusteringTable::StepBound::units(double budget) const {
  const double u = std::floor(budget / quantum);
  return u >= 9.0e18 ? std::numeric_limits<std::uint64_t>::max() / 2 : static_cast<std::uint64_t>(u);
}

ClusteringTable::ClusteringTable(const JointTrack& track, double threshold, TableRows rows)
    : m_track(&track), m_threshold(threshold) {
  assert(threshold >= 0.0 && std::isfinite(threshold));
  const int n = track.frameCount();
  m_ends.assign(static_cast<std::size_t>(n), -1);
  if (rows == TableRows::EndsAndStarts)
    m_starts.resize(static_cast<std::size_t>(n));
  // A joint whose largest possible error is within T: whole-clip runs, no table work.
  m_wholeClip = threshold >= track.maxError();
  if (m_wholeClip) {
    std::fill(m_ends.begin(), m_ends.end(), n - 1);
    std::fill(m_starts.begin(), m_starts.end(), 0);
    return;
  }
  m_bound = buildStepBound(track, threshold, m_evaluations);
  if (rows == TableRows::EndsOnDemand)
    return;
  for (int ref = 0; ref < n; ++ref) {
    m_ends[static_cast<std::size_t>(ref)] = computeRowEnd(ref);
    if (rows == TableRows::EndsAndStarts)
      m_starts[static_cast<std::size_t>(ref)] = scanBackward(track, m_bound, threshold, ref, m_evaluations);
  }
}

int ClusteringTable::computeRowEnd(int ref) const {
  return scanForward(*m_track, m_bound, m_threshold, ref, m_evaluations);
}

} // namespace mlod
