// Key posture, Ahn & Wohn section 4.3, eq. (7) (STEP 6); docs/architecture.md section 4.
#include "core/jpc/key_posture.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numeric>
#include <unordered_map>
#include <vector>

namespace mlod {

namespace {
constexpr int kChunk = 256;            // frames of a row per call of the approximate kernel
constexpr int kLandmarks = 8;          // landmark rows of a long cluster
constexpr int kLandmarkMinFrames = 64; // clusters shorter than this take no landmarks

// Consecutive identical frames inside the range: one evaluation serves them all.
struct Run {
  int frame; // the first frame of the run inside the range
  int count;
};

std::vector<Run> runsOf(const JointTrack& track, FrameRange range) {
  std::vector<Run> runs;
  for (int t = range.first; t <= range.last;) {
    const int end = std::min(track.runLast(t), range.last);
    runs.push_back({t, end - t + 1});
    t = end + 1;
  }
  return runs;
}

// Runs of the range that hold the same posture as an earlier run (the same normalised
// rotation, up to its sign, hence the same rotated child directions): error(t, x) is a
// function of the two frames' postures alone, so such runs give bit-identical errors in
// every row and column. A joint that keeps one pose under float noise (a retargeted finger
// that the source clip does not move) has thousands of frames but a few hundred postures.
struct Postures {
  std::vector<int> of;       // per run: its posture, 0 .. count - 1, numbered by first run
  std::vector<int> firstRun; // per posture: the first run that holds it
  bool repeated() const { return firstRun.size() < of.size(); }
};

Postures posturesOf(const JointTrack& track, const std::vector<Run>& runs) {
  struct Key {
    double w, x, y, z;
    bool operator==(const Key&) const = default;
  };
  struct Hash {
    std::size_t operator()(const Key& k) const {
      const std::hash<double> h;
      return ((h(k.w) * 31 + h(k.x)) * 31 + h(k.y)) * 31 + h(k.z);
    }
  };
  Postures out;
  out.of.reserve(runs.size());
  std::unordered_map<Key, int, Hash> seen;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const glm::dquat& q = track.rotation(runs[i].frame);
    // q and -q are one posture: the sign that makes the first non-zero component positive
    // (+ 0.0 turns -0.0 into 0.0, which == compares equal anyway)
    const double first = q.w != 0.0 ? q.w : q.x != 0.0 ? q.x : q.y != 0.0 ? q.y : q.z;
    const double s = first < 0.0 ? -1.0 : 1.0;
    const Key key{s * q.w + 0.0, s * q.x + 0.0, s * q.y + 0.0, s * q.z + 0.0};
    const auto [found, added] = seen.emplace(key, static_cast<int>(out.firstRun.size()));
    if (added)
      out.firstRun.push_back(static_cast<int>(i));
    out.of.push_back(found->second);
  }
  return out;
}

// error(t, k) for every run t of the range, each distinct posture evaluated once (lazily,
// so a row that stops early costs what it used); the plain evaluation where no posture
// repeats.
class RowErrors {
public:
  RowErrors(const JointTrack& track, const std::vector<Run>& runs, const Postures& postures)
      : m_track(track), m_runs(runs), m_postures(postures),
        m_memo(postures.repeated() ? postures.firstRun.size() : 0, -1.0) {}
  void setRow(int k) {
    m_row = k;
    std::fill(m_memo.begin(), m_memo.end(), -1.0); // errors are >= 0
  }
  double operator()(std::size_t run, std::int64_t& evaluations) {
    if (m_memo.empty()) {
      ++evaluations;
      return m_track.error(m_runs[run].frame, m_row);
    }
    double& error = m_memo[static_cast<std::size_t>(m_postures.of[run])];
    if (error < 0.0) {
      error = m_track.error(m_runs[run].frame, m_row);
      ++evaluations;
    }
    return error;
  }

private:
  const JointTrack& m_track;
  const std::vector<Run>& m_runs;
  const Postures& m_postures;
  std::vector<double> m_memo; // per posture; -1 until evaluated
  int m_row = 0;
};

struct RowResult {
  bool complete = false; // false: over the threshold somewhere, or cannot beat the best
  double sum = 0.0;
  double max = 0.0;
};

// eq. (7) for row k, summed in ascending t; stops as soon as row k cannot win.
RowResult evaluateRow(RowErrors& errors, const std::vector<Run>& runs, int k, double threshold, double bestSum,
                      int bestKey, std::int64_t& evaluations) {
  RowResult row;
  errors.setRow(k);
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const Run& run = runs[i];
    const double error = errors(i, evaluations);
    if (!(error <= threshold))
      return row;
    row.max = std::max(row.max, error);
    for (int c = 0; c < run.count; ++c)
      row.sum += error;
    // what is left only adds (>= 0): a partial sum past the best loses, and so does a tie
    // with a later row
    if (row.sum > bestSum || (row.sum == bestSum && k > bestKey))
      return row;
  }
  row.complete = true;
  return row;
}
} // namespace

KeyPosture keyPosture(const JointTrack& track, FrameRange range, double threshold, const ClusteringTable* table,
                      JpcWorkBudget* budget) {
  assert(range.first >= 0 && range.first <= range.last && range.last < track.frameCount());
  KeyPosture out;
  // The work so far: exact evaluations (out.evaluations) and frames the float kernels went
  // through. The budget is charged what is new once per row tried (a row is O(m)).
  std::int64_t floatFrames = 0, charged = 0;
  const auto overBudget = [&] {
    const std::int64_t work = out.evaluations * kExactEvaluationUnits + floatFrames;
    const std::int64_t units = work - charged;
    charged = work;
    out.work = work;
    out.stopped = out.stopped || (budget != nullptr && !budget->spend(units));
    return out.stopped;
  };
  const std::vector<Run> runs = runsOf(track, range);
  const std::size_t count = runs.size();
  const Postures postures = posturesOf(track, runs);
  RowErrors rowErrors(track, runs, postures);
  const double m = range.length();
  const double eta = errorRoundingBound(track);
  constexpr double kEpsilon = std::numeric_limits<double>::epsilon();

  const auto ruledOutByTable = [&](int k) {
    if (!table)
      return false;
    const int end = table->knownRowEnd(k); // never computes a row here
    return (end >= 0 && end < range.last) || (table->hasStarts() && table->rowStart(k) > range.first);
  };

  double bestSum = std::numeric_limits<double>::infinity();
  int bestKey = -1;
  double bestMax = 0.0;
  const auto offer = [&](int k, const RowResult& row) {
    if (row.complete && (row.sum < bestSum || (row.sum == bestSum && k < bestKey))) {
      bestSum = row.sum;
      bestKey = k;
      bestMax = row.max;
    }
  };

  // The pivot: the run holding the middle frame, evaluated against every run.
  const int middle = range.first + range.length() / 2;
  std::size_t pivot = 0;
  while (runs[pivot].frame + runs[pivot].count <= middle)
    ++pivot;
  std::vector<double> pivotErrors(count);
  RowResult pivotRow;
  pivotRow.complete = !ruledOutByTable(runs[pivot].frame);
  rowErrors.setRow(runs[pivot].frame);
  for (std::size_t i = 0; i < count; ++i) {
    const double error = rowErrors(i, out.evaluations);
    pivotErrors[i] = error;
    pivotRow.complete = pivotRow.complete && error <= threshold;
    pivotRow.max = std::max(pivotRow.max, error);
    for (int c = 0; c < runs[i].count; ++c)
      pivotRow.sum += error;
  }
  offer(runs[pivot].frame, pivotRow);
  const auto finish = [&] {
    if (overBudget())
      bestKey = -1;
    out.key = bestKey;
    out.errorSum = bestKey >= 0 ? bestSum : 0.0;
    out.maxError = bestKey >= 0 ? bestMax : 0.0;
    return out;
  };
  if (count == 1)
    return finish();

  // Lower bounds: sum_t |E(t, p) - E(k, p)| = v C_below - S_below + S_above - v C_above.
  std::vector<std::size_t> byError(count);
  std::iota(byError.begin(), byError.end(), std::size_t{0});
  std::sort(byError.begin(), byError.end(), [&](std::size_t x, std::size_t y) {
    return pivotErrors[x] != pivotErrors[y] ? pivotErrors[x] < pivotErrors[y] : x < y;
  });
  std::vector<double> sortedErrors(count), prefixCount(count + 1, 0.0), prefixSum(count + 1, 0.0);
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t r = byError[i];
    sortedErrors[i] = pivotErrors[r];
    prefixCount[i + 1] = prefixCount[i] + runs[r].count;
    prefixSum[i + 1] = prefixSum[i] + runs[r].count * pivotErrors[r];
  }
  const double total = prefixSum[count];
  const double lowest = sortedErrors.front(), highest = sortedErrors.back();
  std::vector<double> bound(count);
  for (std::size_t i = 0; i < count; ++i) {
    const double v = pivotErrors[i];
    const std::size_t below =
        static_cast<std::size_t>(std::lower_bound(sortedErrors.begin(), sortedErrors.end(), v) - sortedErrors.begin());
    bound[i] =
        (v * prefixCount[below] - prefixSum[below]) + ((total - prefixSum[below]) - v * (m - prefixCount[below]));
  }
  // Landmarks (long clusters): a few approximate rows p, chosen farthest-first, bound each
  // row k below frame by frame, sum_t max_p |E(t, p) - E(k, p)|, far tighter than one
  // pivot's sum (the metric has a few dimensions: a direction and a rotation).
  const double delta = track.approximationBound();
  const int length = range.length();
  const int landmarks = length >= kLandmarkMinFrames ? kLandmarks : 0;
  std::vector<float> landmarkRows(static_cast<std::size_t>(landmarks) * static_cast<std::size_t>(length));
  std::vector<int> landmarkFrames(static_cast<std::size_t>(landmarks));
  if (landmarks > 0) {
    std::vector<float> nearest(static_cast<std::size_t>(length), std::numeric_limits<float>::infinity());
    int frame = runs[pivot].frame;
    for (int p = 0; p < landmarks; ++p) {
      landmarkFrames[static_cast<std::size_t>(p)] = frame;
      float* row = &landmarkRows[static_cast<std::size_t>(p) * static_cast<std::size_t>(length)];
      track.approximateErrors(frame, range.first, length, row);
      floatFrames += length;
      std::size_t farthest = 0;
      for (std::size_t t = 0; t < nearest.size(); ++t) {
        nearest[t] = std::min(nearest[t], row[t]);
        if (nearest[t] > nearest[farthest])
          farthest = t;
      }
      frame = range.first + static_cast<int>(farthest);
    }
  }
  // Per term, the exact error is at least |row difference| - 2 (delta + eta) - eta; the
  // float sums lose far less than 1e-4 relative.
  const double landmarkSlack = 2.0 * delta + 3.0 * eta;
  const auto landmarkRules = [&](int k, double upper) {
    float at[kLandmarks];
    const std::size_t column = static_cast<std::size_t>(k - range.first);
    for (int p = 0; p < landmarks; ++p)
      at[p] = landmarkRows[static_cast<std::size_t>(p) * static_cast<std::size_t>(length) + column];
    double lower = 0.0;
    for (int first = 0; first < length; first += kChunk) {
      const int chunk = std::min(kChunk, length - first);
      lower += landmarkDistanceSum(landmarkRows.data(), landmarks, static_cast<std::size_t>(length), at, first, chunk);
      floatFrames += chunk;
      if (lower - (first + chunk) * landmarkSlack - 1e-4 * lower > upper)
        return true;
    }
    return false;
  };

  // Each landmark p also bounds every row's whole sum at once, as the pivot does:
  // sum_t |E(t, p) - E(k, p)| from sorted prefix sums, O(log m) per row, from the landmark's
  // exact errors (the float rows' slack, m delta, can exceed the spread of the sums of a
  // slow motion). On a motion along one path (a slow turn) a landmark at its end makes this
  // the row's sum itself, so only the rows near the best are ever summed: O(m log m) in
  // all, not m^2 (a 50,000-frame turn took 41 s).
  std::vector<double> landmarkLower(count, 0.0);
  if (landmarks > 0) {
    std::vector<double> exact(static_cast<std::size_t>(length)), sorted(exact.size()), prefix(exact.size() + 1);
    for (const int p : landmarkFrames) {
      rowErrors.setRow(p);
      for (std::size_t i = 0; i < count; ++i) {
        const Run& run = runs[i];
        const double error = rowErrors(i, out.evaluations);
        std::fill_n(exact.begin() + (run.frame - range.first), run.count, error);
      }
      sorted = exact;
      std::sort(sorted.begin(), sorted.end());
      prefix[0] = 0.0;
      for (std::size_t t = 0; t < sorted.size(); ++t)
        prefix[t + 1] = prefix[t] + sorted[t];
      const double sum = prefix.back();
      for (std::size_t i = 0; i < count; ++i) {
        const double v = exact[static_cast<std::size_t>(runs[i].frame - range.first)];
        const std::size_t below =
            static_cast<std::size_t>(std::lower_bound(sorted.begin(), sorted.end(), v) - sorted.begin());
        const double lower = (v * static_cast<double>(below) - prefix[below]) +
                             ((sum - prefix[below]) - v * static_cast<double>(exact.size() - below));
        // per term: each computed error within eta of the pseudometric; the sums and their
        // differences: m epsilon of the whole
        landmarkLower[i] = std::max(landmarkLower[i], lower - 3.0 * m * eta - 4.0 * m * kEpsilon * (sum + v * m));
      }
    }
  }
  // Rows by their best lower bound: once one is past the best upper bound, so are the rest.
  const auto margin = [&](std::size_t i) {
    // rounding: each computed error is within eta of the pseudometric; sums of m terms lose
    // at most m epsilon relative
    return 3.0 * m * eta + 4.0 * m * kEpsilon * (bound[i] + total + pivotErrors[i] * m);
  };
  std::vector<double> rowLower(count);
  for (std::size_t i = 0; i < count; ++i)
    rowLower[i] = std::max(bound[i] - margin(i), landmarkLower[i]);
  std::vector<std::size_t> order(count);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(),
            [&](std::size_t x, std::size_t y) { return rowLower[x] != rowLower[y] ? rowLower[x] < rowLower[y] : x < y; });

  // Approximate phase: the float kernel over every frame gives each surviving row its
  // sum to within m delta; rows that cannot beat the best upper bound drop out early.
  struct Survivor {
    double lower; // of the row's exact sum
    std::size_t run;
  };
  std::vector<Survivor> survivors;
  std::vector<float> approximate(static_cast<std::size_t>(std::min(range.length(), kChunk)));
  double upperBest = bestSum; // the winner's exact sum is at most this
  for (const std::size_t i : order) {
    if (overBudget())
      return finish();
    if (i == pivot)
      continue;
    // a later run of an earlier run's posture has the same sum: only the earlier can win
    if (postures.firstRun[static_cast<std::size_t>(postures.of[i])] != static_cast<int>(i))
      continue;
    const int k = runs[i].frame;
    const double v = pivotErrors[i];
    // E(t, k) >= |E(t, p) - E(k, p)|: some frame is over the threshold.
    if (std::max(v - lowest, highest - v) - 2.0 * eta > threshold)
      continue;
    if (rowLower[i] > upperBest)
      break;
    if (ruledOutByTable(k))
      continue;
    if (landmarks > 0 && landmarkRules(k, upperBest))
      continue;
    double sum = 0.0, largest = 0.0;
    bool dropped = false;
    for (int first = range.first; first <= range.last && !dropped; first += kChunk) {
      const int chunk = std::min(kChunk, range.last - first + 1);
      track.approximateErrors(k, first, chunk, approximate.data());
      floatFrames += chunk;
      for (int c = 0; c < chunk; ++c) {
        sum += approximate[static_cast<std::size_t>(c)];
        largest = std::max(largest, static_cast<double>(approximate[static_cast<std::size_t>(c)]));
      }
      const double done = first + chunk - range.first;
      dropped = largest - delta > threshold || // surely over the threshold somewhere
                sum - done * delta - 4.0 * done * kEpsilon * (sum + done * delta) > upperBest;
    }
    if (dropped)
      continue;
    const double slack = m * delta + 4.0 * m * kEpsilon * (sum + m * delta);
    if (largest + delta <= threshold) // surely feasible
      upperBest = std::min(upperBest, sum + slack);
    survivors.push_back({sum - slack, i});
  }

  // Exact phase: the few rows whose sum may still be the least, by increasing bound.
  std::sort(survivors.begin(), survivors.end(), [](const Survivor& a, const Survivor& b) {
    return a.lower != b.lower ? a.lower < b.lower : a.run < b.run;
  });
  for (const Survivor& survivor : survivors) {
    if (survivor.lower > upperBest || overBudget())
      break;
    const int k = runs[survivor.run].frame;
    offer(k, evaluateRow(rowErrors, runs, k, threshold, bestSum, bestKey, out.evaluations));
    upperBest = std::min(upperBest, bestSum);
  }
  return finish();
}

} // namespace mlod
