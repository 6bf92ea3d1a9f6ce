#include "unit/core/jpc/reference.h"

#include <algorithm>
#include <cstddef>

namespace mlod::test {

namespace {
double at(const std::vector<double>& table, int n, int t, int ref) {
  return table[static_cast<std::size_t>(ref) * static_cast<std::size_t>(n) + static_cast<std::size_t>(t)];
}
} // namespace

std::vector<double> fullTable(const JointTrack& track) {
  const int n = track.frameCount();
  std::vector<double> table(static_cast<std::size_t>(n) * static_cast<std::size_t>(n));
  for (int ref = 0; ref < n; ++ref)
    for (int t = 0; t < n; ++t)
      table[static_cast<std::size_t>(ref) * static_cast<std::size_t>(n) + static_cast<std::size_t>(t)] =
          track.error(t, ref);
  return table;
}

std::vector<int> referenceRowEnds(const std::vector<double>& table, int n, double threshold) {
  std::vector<int> ends(static_cast<std::size_t>(n));
  for (int ref = 0; ref < n; ++ref) {
    int e = ref;
    while (e + 1 < n && at(table, n, e + 1, ref) <= threshold)
      ++e;
    ends[static_cast<std::size_t>(ref)] = e;
  }
  return ends;
}

std::vector<int> referenceRowStarts(const std::vector<double>& table, int n, double threshold) {
  std::vector<int> starts(static_cast<std::size_t>(n));
  for (int ref = 0; ref < n; ++ref) {
    int s = ref;
    while (s > 0 && at(table, n, s - 1, ref) <= threshold)
      --s;
    starts[static_cast<std::size_t>(ref)] = s;
  }
  return starts;
}

std::vector<FrameRange> referenceGreedyRanges(std::vector<int> rowEnds) {
  const int n = static_cast<int>(rowEnds.size());
  std::vector<bool> alive(static_cast<std::size_t>(n));
  for (int s = 0; s < n; ++s)
    alive[static_cast<std::size_t>(s)] = rowEnds[static_cast<std::size_t>(s)] - s + 1 >= 3;
  std::vector<FrameRange> clusters;
  for (;;) {
    int best = -1;
    for (int s = 0; s < n; ++s)
      if (alive[static_cast<std::size_t>(s)] &&
          (best < 0 || rowEnds[static_cast<std::size_t>(s)] - s > rowEnds[static_cast<std::size_t>(best)] - best))
        best = s;
    if (best < 0)
      break;
    const FrameRange taken{best, rowEnds[static_cast<std::size_t>(best)]};
    clusters.push_back(taken);
    for (int s = 0; s < n; ++s) {
      if (!alive[static_cast<std::size_t>(s)])
        continue;
      int& end = rowEnds[static_cast<std::size_t>(s)];
      if (s >= taken.first && s <= taken.last)
        alive[static_cast<std::size_t>(s)] = false; // starts inside: dropped
      else if (s < taken.first && end >= taken.first)
        end = taken.first - 1; // cut
      if (end - s + 1 < 3)
        alive[static_cast<std::size_t>(s)] = false;
    }
  }
  std::sort(clusters.begin(), clusters.end(),
            [](const FrameRange& a, const FrameRange& b) { return a.first < b.first; });
  return clusters;
}

int referenceKey(const std::vector<double>& table, int n, FrameRange range, double threshold) {
  int key = -1;
  double bestSum = 0.0;
  for (int k = range.first; k <= range.last; ++k) {
    double sum = 0.0;
    bool feasible = true;
    for (int t = range.first; t <= range.last; ++t) {
      const double e = at(table, n, t, k);
      feasible = feasible && e <= threshold;
      sum += e;
    }
    if (feasible && (key < 0 || sum < bestSum)) {
      key = k;
      bestSum = sum;
    }
  }
  return key;
}

Coverage referenceOptimalCoverage(const std::vector<double>& table, int n, double threshold) {
  // feasible(a, b): some k in [a, b] within the threshold of every frame of [a, b], that
  // is, whose run around the diagonal holds [a, b]
  const std::vector<int> starts = referenceRowStarts(table, n, threshold);
  const std::vector<int> ends = referenceRowEnds(table, n, threshold);
  const auto feasible = [&](int a, int b) {
    for (int k = a; k <= b; ++k)
      if (starts[static_cast<std::size_t>(k)] <= a && ends[static_cast<std::size_t>(k)] >= b)
        return true;
    return false;
  };
  std::vector<Coverage> best(static_cast<std::size_t>(n) + 1); // best[i]: frames [0, i)
  for (int b = 0; b < n; ++b) {
    Coverage c = best[static_cast<std::size_t>(b)];
    for (int a = 0; a + 2 <= b; ++a) {
      const Coverage before = best[static_cast<std::size_t>(a)];
      const Coverage candidate{before.frames + b - a + 1, before.clusters + 1};
      const bool better =
          candidate.frames > c.frames || (candidate.frames == c.frames && candidate.clusters < c.clusters);
      if (better && feasible(a, b))
        c = candidate;
    }
    best[static_cast<std::size_t>(b) + 1] = c;
  }
  return best[static_cast<std::size_t>(n)];
}

} // namespace mlod::test
