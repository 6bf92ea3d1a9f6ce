#pragma once

#include "cli/cli_common.h"

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace mlod::cli {

// `motionlod simplify FILE [--clip NAME|INDEX] --threshold E[,E…] [--alpha A]
//  [--joint NAME=E …] [--mode greedy|optimal] [--unit-scale S] [--json]`:
// joint posture clustering of one clip at one or more thresholds (DESIGN.md sections 4, 6).
struct SimplifyCommand {
  std::string file;
  std::string clip;                         // name or index; empty = the first clip
  std::vector<std::string> thresholds;      // cm·degrees, one per level (parsed in run(): errors name the file)
  std::string alpha = "5";                  // cm
  std::vector<std::string> jointThresholds; // NAME=E, for every level
  std::string mode = "greedy";
  bool json = false;
  ImportArguments import;

  void attach(CLI::App& app);
  int run() const;
};

} // namespace mlod::cli
