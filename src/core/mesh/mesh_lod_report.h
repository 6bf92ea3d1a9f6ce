#pragma once
// The JSON document of `motionlod meshlod --json` (docs/architecture.md section 6): keys exactly
//   {"file","triangles","vertices","locked_vertices",
//    "levels":[{"ratio","triangles","vertices","max_error","error_cm":{"bind","animated_max",
//               "animated_mean"},"shared_vertices_preserved","warning","seconds"}]}
// Units: errors in cm (symmetric max distance to the original, mesh_lod.h): max_error the
// largest of bind and animated_max; animated_* over the measured poses, frames other than
// those the simplification saw; seconds of wall clock. "warning" is null unless the ratio's
// triangle count could not be reached; "locked_vertices" counts the welded vertices locked as
// non-manifold, and "shared_vertices_preserved" (the key kept from the per-segment
// simplifier) is true when every one of them kept its position.

#include "core/mesh/mesh_lod.h"

#include <string>
#include <vector>

namespace mlod {

struct MeshLodReport {
  struct Level {
    double ratio = 1.0;
    std::size_t triangles = 0;
    std::size_t vertices = 0;
    double maxErrorCm = 0.0;
    double bindErrorCm = 0.0;
    double animatedMaxErrorCm = 0.0;
    double animatedMeanErrorCm = 0.0;
    bool lockedVerticesPreserved = true;
    std::string warning; // empty = none (null in JSON)
    double seconds = 0.0;
  };
  std::string file;
  std::size_t triangles = 0; // the original mesh
  std::size_t vertices = 0;
  int lockedVertices = 0; // welded vertices that never collapse (non-manifold guards)
  std::vector<Level> levels;
};

// One report level from a mesh level, its simplification time (seconds) given.
MeshLodReport::Level reportLevel(const MeshLodLevel& level, double seconds);

std::string meshLodReportJson(const MeshLodReport& report, int indent = 2);

} // namespace mlod
