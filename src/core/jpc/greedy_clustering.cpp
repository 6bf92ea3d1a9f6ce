// Greedy clustering, Ahn & Wohn section 4.2, STEPs 2-5; docs/architecture.md section 4.
#include "core/jpc/greedy_clustering.h"

#include <cassert>
#include <iterator>
#include <map>
#include <queue>

namespace mlod {

namespace {
struct Candidate {
  int length;
  int first;
  // Longest first; ties: the earliest start.
  bool operator<(const Candidate& other) const {
    return length != other.length ? length < other.length : first > other.first;
  }
};
} // namespace

std::vector<FrameRange> greedyRanges(std::span<const int> rowEnds) {
  return greedyRanges(static_cast<int>(rowEnds.size()),
                      [&](int ref) { return rowEnds[static_cast<std::size_t>(ref)]; });
}

std::vector<FrameRange> greedyRanges(int frameCount, const std::function<int(int)>& rowEnd) {
  const int n = frameCount;
  // note: lengths only ever shrink (a cut ends a range just before the nearest chosen
  // cluster after its start; a row's true end is at most the clip's), so a lazy max-heap
  // is exact: an entry whose stored length is still current when it surfaces is the true
  // longest remaining range, and earlier starts surface first among equal lengths.
  std::priority_queue<Candidate> heap;
  std::vector<int> ends(static_cast<std::size_t>(n), -1); // -1: not asked yet
  for (int first = 0; first + kMinClusterFrames <= n; ++first)
    heap.push({n - first, first});
  std::map<int, int> chosen; // first -> last
  while (!heap.empty()) {
    const Candidate top = heap.top();
    heap.pop();
    const auto next = chosen.upper_bound(top.first);
    if (next != chosen.begin() && std::prev(next)->second >= top.first)
      continue; // starts inside a chosen cluster: dropped
    int& end = ends[static_cast<std::size_t>(top.first)];
    if (end < 0) {
      end = rowEnd(top.first);
      assert(end >= top.first && end < n);
    }
    int last = end;
    if (next != chosen.end() && next->first <= last)
      last = next->first - 1; // cut
    const int length = last - top.first + 1;
    if (length < kMinClusterFrames)
      continue;
    if (length < top.length) {
      heap.push({length, top.first});
      continue;
    }
    chosen.emplace(top.first, last);
  }
  std::vector<FrameRange> out;
  out.reserve(chosen.size());
  for (const auto& [first, last] : chosen)
    out.push_back({first, last});
  return out;
}

} // namespace mlod
