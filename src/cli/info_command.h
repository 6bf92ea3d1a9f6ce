#pragma once

#include "cli/cli_common.h"

namespace CLI { class App; }

namespace mlod::cli {

// `motionlod info FILE [--json]`: joints, clips, meshes and unit of a file.
// Returns a function to run after parsing.
struct InfoCommand {
  std::string file;
  bool json = false;
  ImportArguments import;

  void attach(CLI::App& app);
  int run() const;
};

} // namespace mlod::cli
