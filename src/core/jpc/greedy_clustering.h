#pragma once
// The paper's greedy cluster selection (Ahn & Wohn, section 4.2, STEPs 2-5), with the
// tie rules of docs/architecture.md section 4.

#include "core/jpc/cluster_set.h"

#include <functional>
#include <span>
#include <vector>

namespace mlod {

// `rowEnds[ref]` is row ref's available range end (ClusteringTable::rowEnd, >= ref).
// Repeats: take the longest remaining range (ties: the earliest start), make it a
// cluster, delete it, and cut every remaining range that overlaps it: a range starting
// before it ends just before it, one starting inside it is dropped. Ranges shorter than
// kMinClusterFrames are dropped. Returns the clusters' frame ranges, sorted by first
// frame. O(n log n) time, O(n) memory.
std::vector<FrameRange> greedyRanges(std::span<const int> rowEnds);

// The same selection, asking rowEnd(ref) only for rows that may still hold the longest
// range: a row is first taken at its most optimistic length (to the clip's end) and asked
// when that surfaces, so rows inside a long cluster chosen early are never computed (at
// large thresholds, most of them). The same result as the overload above.
std::vector<FrameRange> greedyRanges(int frameCount, const std::function<int(int)>& rowEnd);

} // namespace mlod
