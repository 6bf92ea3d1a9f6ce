#pragma once

#include "cli/cli_common.h"

namespace CLI { class App; }

namespace mlod::cli {

// `motionlod info FILE|PROJECT.mlod [--json]`: joints, clips, meshes and unit of a file; for
// a project, its settings, LOD levels and mappings, and each asset as the project opens it
// (its unit scale; a missing file is reported, the exit status is then 2).
struct InfoCommand {
  std::string file;
  bool json = false;
  ImportArguments import;
  ProjectFileOptions project;

  void attach(CLI::App& app);
  int run() const;
};

} // namespace mlod::cli
