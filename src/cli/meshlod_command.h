#pragma once

#include "cli/cli_common.h"

#include <string>
#include <vector>

namespace CLI { class App; }

namespace mlod::cli {

// `motionlod meshlod FILE --ratio R[,R…] [--json]`: mesh LOD per joint segment of the
// file's character mesh (issue 5): per ratio the triangles and vertices reached, the error
// in cm against the original (bind pose and animated poses of the file's clips), whether
// every shared and border vertex stayed, a warning where the locks stop short of the ratio.
struct MeshLodCommand {
  std::string file;
  std::vector<std::string> ratios; // (0, 1], parsed in run() so that errors name the file
  bool json = false;
  ImportArguments import;

  void attach(CLI::App& app);
  int run() const;
};

} // namespace mlod::cli
