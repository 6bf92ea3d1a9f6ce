#pragma once
// The result of joint posture clustering for one clip (docs/architecture.md section 3): per joint,
// sorted disjoint clusters of consecutive frames, each frozen at one key posture.

#include "core/error.h"

#include <vector>

namespace mlod {

// Inclusive frame indices.
struct FrameRange {
  int first = 0;
  int last = 0;
  int length() const { return last - first + 1; }
  friend bool operator==(const FrameRange&, const FrameRange&) = default;
};

struct Cluster {
  int first = 0; // first frame, inclusive
  int last = 0;  // last frame, inclusive; last - first + 1 >= 3
  int key = 0;   // the key posture's frame, first <= key <= last
  int length() const { return last - first + 1; }
  friend bool operator==(const Cluster&, const Cluster&) = default;
};

inline constexpr int kMinClusterFrames = 3; // the paper: "The cluster length must be greater than 2"

class ClusterSet {
public:
  int frameCount = 0;                       // frames of the clip the clusters belong to
  std::vector<std::vector<Cluster>> joints; // per skeleton joint; empty = never simplified

  int jointCount() const { return static_cast<int>(joints.size()); }
  // Index of the cluster of `joint` that holds `frame`, or -1.
  int clusterAt(int joint, int frame) const;
  int clusterCount() const;
  int clusteredFrames(int joint) const;

  // Rules: every cluster has kMinClusterFrames frames or more, lies in [0, frameCount) and
  // holds its key; each joint's clusters are sorted and disjoint.
  Error validate() const;
};

} // namespace mlod
