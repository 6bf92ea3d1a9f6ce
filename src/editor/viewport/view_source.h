#pragma once
// What the 3D views show for the document's current asset, clip and level: the skeleton and
// meshes to draw, the original clip and the simplified one (the level's JPC clusters), on
// the asset's own skeleton or, through a motion mapping (core/mapping/motion_mapping.h), on
// the character the motion is assigned to. Glue over core calls; no algorithm of its own.

#include "core/asset.h"
#include "core/jpc/cluster_set.h"

#include <QString>

#include <memory>
#include <optional>
#include <vector>

namespace mlod {

class Document;

struct ViewSource {
  std::shared_ptr<const Asset> motion;    // the asset in view
  std::shared_ptr<const Asset> character; // what is drawn: the motion itself, or the mapped character
  int motionAsset = -1;
  int characterAsset = -1;
  int mapping = -1;         // index in project().mappings, or -1 (own skeleton)
  int level = 0;            // the level the simplified clip shows
  bool simplifiedReady = false; // the level's clusters have landed (else simplified = original)
  Skeleton skeleton;        // the drawn skeleton (a single joint for a mesh without skeleton)
  std::vector<const SkinnedMesh*> meshes; // into `character`; empty: bone capsules
  Clip original;            // on `skeleton`
  Clip simplified;          // on `skeleton`
  std::optional<ClusterSet> clusters; // the level's clusters on the motion's skeleton (own: `skeleton`)
  std::vector<int> motionJoint;       // per drawn joint: the motion joint it follows, or -1
  QString description;      // for the overlay
  QString error;            // non-empty: nothing to show, and why

  bool valid() const { return error.isEmpty(); }
  // Joints of `skeleton` frozen (inside a cluster of their motion joint) at `frame`.
  std::vector<bool> frozenAt(int frame) const;
};

// `mapping` = -1 shows the asset on its own skeleton; an index of project().mappings whose
// motion is the asset in view plays it on that mapping's character.
ViewSource makeViewSource(const Document& document, int mapping = -1);

// The mappings that play the asset in view on a character (indices into project().mappings).
std::vector<int> mappingsOfCurrentAsset(const Document& document);

} // namespace mlod
