#pragma once

#include "cli/cli_common.h"

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace mlod::cli {

// `motionlod simplify FILE|PROJECT.mlod [--clip NAME|INDEX] --threshold E[,E…] [--alpha A]
//  [--joint NAME=E …] [--mode greedy|optimal] [--unit-scale S] [--json]`:
// joint posture clustering of one clip at one or more thresholds (docs/architecture.md sections 4, 6).
//
// A project (.mlod) gives what the editor shows: the asset and clip in view (the first asset
// when none), its unit scale, the project's alpha and mode, every per-joint alpha, lock and
// threshold override, and one threshold per LOD level after the original (level i of the
// project is entry i - 1 of "thresholds"). Flags override: --alpha, --mode, --unit-scale,
// --clip; --joint sets a joint's threshold at every level; --threshold replaces the levels
// and with them the per-joint threshold overrides (alphas and locks stay). A file needs --threshold.
struct SimplifyCommand {
  std::string file;
  std::string clip;                         // name or index; empty = the first clip
  std::vector<std::string> thresholds;      // cm·degrees, one per level (parsed in run(): errors name the file); empty: the project's
  std::string alpha;                        // cm; empty: kDefaultJpcAlpha
  std::vector<std::string> jointThresholds; // NAME=E, for every level
  std::string mode = "greedy";
  bool json = false;
  ImportArguments import;
  ProjectFileOptions projectOptions;
  const CLI::App* subcommand = nullptr; // set by attach(): tells a flag given from its default

  void attach(CLI::App& app);
  int run() const;
};

} // namespace mlod::cli
