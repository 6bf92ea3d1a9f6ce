#pragma once
// The JSON document of `motionlod meshlod --json` (issue 5; docs/architecture.md section 6): keys exactly
//   {"file","triangles","vertices","locked_vertices",
//    "levels":[{"ratio","triangles","vertices","max_error","shared_vertices_preserved",
//               "warning","seconds"}]}
// Units: max_error in cm (the level's symmetric max distance to the original, the largest
// over the bind pose and the measured animated poses); seconds of wall clock. "warning" is
// null unless the ratio's triangle count could not be reached; "shared_vertices_preserved"
// is true only when every shared and border vertex kept its position.

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
    bool sharedVerticesPreserved = true;
    std::string warning; // empty = none (null in JSON)
    double seconds = 0.0;
  };
  std::string file;
  std::size_t triangles = 0; // the original mesh
  std::size_t vertices = 0;
  int lockedVertices = 0;    // vertices that never collapse (shared between joints, on a border)
  std::vector<Level> levels;
};

// One report level from a mesh level, its simplification time (seconds) given.
MeshLodReport::Level reportLevel(const MeshLodLevel& level, double seconds);

std::string meshLodReportJson(const MeshLodReport& report, int indent = 2);

} // namespace mlod
