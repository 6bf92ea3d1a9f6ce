// Greedy clustering, Ahn & Wohn section 4.2, STEPs 2-5; DESIGN.md section 4.
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
  const int n = static_cast<int>(rowEnds.size());
  // note: lengths only ever shrink (a cut ends a range just before the nearest chosen
  // cluster after its start), so a lazy max-heap is exact: an entry whose stored length
  // is still current when it surfaces is the true longest remaining range.
  std::priority_queue<Candidate> heap;
  for (int first = 0; first < n; ++first) {
    assert(rowEnds[static_cast<std::size_t>(first)] >= first && rowEnds[static_cast<std::size_t>(first)] < n);
    const int length = rowEnds[static_cast<std::size_t>(first)] - first + 1;
    if (length >= kMinClusterFrames)
      heap.push({length, first});
  }
  std::map<int, int> chosen; // first -> last
  while (!heap.empty()) {
    const Candidate top = heap.top();
    heap.pop();
    int last = rowEnds[static_cast<std::size_t>(top.first)];
    const auto next = chosen.upper_bound(top.first);
    if (next != chosen.begin() && std::prev(next)->second >= top.first)
      continue; // starts inside a chosen cluster: dropped
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
