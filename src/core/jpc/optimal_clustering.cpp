// Optimal clustering under the JPC error bound; docs/architecture.md section 4 (beyond the paper).
#include "core/jpc/optimal_clustering.h"

#include <algorithm>
#include <cassert>
#include <cstdint>
#include <queue>

namespace mlod {

namespace {
// Range maximum with point updates; ties go to the smaller index.
class MaxTree {
public:
  explicit MaxTree(int size) {
    while (m_leaves < size)
      m_leaves *= 2;
    m_nodes.assign(static_cast<std::size_t>(2 * m_leaves), {kNone, -1});
  }
  void set(int index, std::int64_t value) {
    std::size_t node = static_cast<std::size_t>(index + m_leaves);
    m_nodes[node] = {value, index};
    for (node /= 2; node >= 1; node /= 2)
      m_nodes[node] = better(m_nodes[2 * node], m_nodes[2 * node + 1]);
  }
  // Maximum over [lo, hi] (inclusive) and where it is.
  std::pair<std::int64_t, int> query(int lo, int hi) const {
    std::pair<std::int64_t, int> left{kNone, -1}, right{kNone, -1};
    std::size_t l = static_cast<std::size_t>(lo + m_leaves), r = static_cast<std::size_t>(hi + m_leaves + 1);
    while (l < r) {
      if (l & 1)
        left = better(left, m_nodes[l++]);
      if (r & 1)
        right = better(m_nodes[--r], right);
      l /= 2;
      r /= 2;
    }
    return better(left, right);
  }

private:
  static constexpr std::int64_t kNone = INT64_MIN;
  static std::pair<std::int64_t, int> better(const std::pair<std::int64_t, int>& a,
                                             const std::pair<std::int64_t, int>& b) {
    if (a.first != b.first)
      return a.first > b.first ? a : b;
    if (a.second < 0)
      return b;
    if (b.second < 0)
      return a;
    return a.second <= b.second ? a : b;
  }
  int m_leaves = 1;
  std::vector<std::pair<std::int64_t, int>> m_nodes;
};

struct KeyEntry {
  std::int64_t value; // the best h(a) over the key's whole window start
  int start;          // where that best is
  int key;
  int end; // the key's window end: usable while b <= end
  bool operator<(const KeyEntry& other) const {
    if (value != other.value)
      return value < other.value;
    return key > other.key; // ties: the earlier key
  }
};
} // namespace

std::vector<FrameRange> optimalRanges(std::span<const int> rowStarts, std::span<const int> rowEnds) {
  assert(rowStarts.size() == rowEnds.size());
  const int n = static_cast<int>(rowEnds.size());
  if (n < kMinClusterFrames)
    return {};
  // Score of a partition of a prefix: covered * W - clusters, W > any cluster count, so
  // one integer orders by most frames covered, then fewest clusters.
  const std::int64_t W = n + 1;
  std::vector<std::int64_t> best(static_cast<std::size_t>(n) + 1, 0); // best[i]: frames [0, i)
  std::vector<int> choice(static_cast<std::size_t>(n), -1);           // cluster start ending at b, or -1
  // h(a) = best[a] - a W: a cluster [a, b] scores h(a) + (b + 1) W - 1.
  MaxTree h(n);
  std::priority_queue<KeyEntry> keys; // keys k <= b - 2 whose window reaches b (lazy removal)
  for (int b = 0; b < n; ++b) {
    h.set(b, best[static_cast<std::size_t>(b)] - b * W);
    const int full = b - 2; // from now on, any start of this key's window makes >= 3 frames
    if (full >= 0 && rowEnds[static_cast<std::size_t>(full)] >= b) {
      assert(rowStarts[static_cast<std::size_t>(full)] <= full);
      const auto [value, start] = h.query(rowStarts[static_cast<std::size_t>(full)], full);
      keys.push({value, start, full, rowEnds[static_cast<std::size_t>(full)]});
    }
    std::int64_t score = best[static_cast<std::size_t>(b)]; // frame b left uncovered
    int start = -1;
    const auto consider = [&](std::int64_t value, int a) {
      const std::int64_t candidate = value + (b + 1) * W - 1;
      if (candidate > score) {
        score = candidate;
        start = a;
      }
    };
    while (!keys.empty() && keys.top().end < b)
      keys.pop();
    if (!keys.empty())
      consider(keys.top().value, keys.top().start);
    // Keys at b - 1 and b: only starts up to b - 2 make a cluster of 3 frames.
    for (int k = std::max(0, b - 1); k <= b; ++k) {
      if (rowEnds[static_cast<std::size_t>(k)] >= b && rowStarts[static_cast<std::size_t>(k)] <= b - 2) {
        const auto [value, a] = h.query(rowStarts[static_cast<std::size_t>(k)], b - 2);
        consider(value, a);
      }
    }
    best[static_cast<std::size_t>(b) + 1] = score;
    choice[static_cast<std::size_t>(b)] = start;
  }
  std::vector<FrameRange> out;
  for (int b = n - 1; b >= 0;) {
    const int a = choice[static_cast<std::size_t>(b)];
    if (a < 0) {
      --b;
      continue;
    }
    out.push_back({a, b});
    b = a - 1;
  }
  std::reverse(out.begin(), out.end());
  return out;
}

} // namespace mlod
