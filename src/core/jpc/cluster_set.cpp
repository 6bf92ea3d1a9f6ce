#include "core/jpc/cluster_set.h"

#include <algorithm>
#include <string>

namespace mlod {

int ClusterSet::clusterAt(int joint, int frame) const {
  const std::vector<Cluster>& clusters = joints[static_cast<std::size_t>(joint)];
  const auto after =
      std::upper_bound(clusters.begin(), clusters.end(), frame, [](int f, const Cluster& c) { return f < c.first; });
  if (after == clusters.begin())
    return -1;
  const auto candidate = after - 1;
  return frame <= candidate->last ? static_cast<int>(candidate - clusters.begin()) : -1;
}

int ClusterSet::clusterCount() const {
  std::size_t count = 0;
  for (const std::vector<Cluster>& clusters : joints)
    count += clusters.size();
  return static_cast<int>(count);
}

int ClusterSet::clusteredFrames(int joint) const {
  int frames = 0;
  for (const Cluster& cluster : joints[static_cast<std::size_t>(joint)])
    frames += cluster.length();
  return frames;
}

Error ClusterSet::validate() const {
  for (std::size_t j = 0; j < joints.size(); ++j) {
    int previousLast = -1;
    for (const Cluster& c : joints[j]) {
      const std::string where = "joint " + std::to_string(j) + ": cluster [" + std::to_string(c.first) + ", " +
                                std::to_string(c.last) + "] key " + std::to_string(c.key);
      if (c.length() < kMinClusterFrames)
        return Error(where + " has fewer than " + std::to_string(kMinClusterFrames) + " frames");
      if (c.first < 0 || c.last >= frameCount)
        return Error(where + " lies outside the clip's " + std::to_string(frameCount) + " frames");
      if (c.key < c.first || c.key > c.last)
        return Error(where + " does not hold its key");
      if (c.first <= previousLast)
        return Error(where + " overlaps or precedes the cluster before it");
      previousLast = c.last;
    }
  }
  return {};
}

} // namespace mlod
