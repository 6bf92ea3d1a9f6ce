#pragma once

#include "cli/cli_common.h"
#include "cli/export_job.h"

#include <string>
#include <vector>

namespace CLI { class App; }

namespace mlod::cli {

// `motionlod export FILE|PROJECT.mlod --plugin ID -o OUT [--levels 0,2,3] [--option k=v …]
//  [--mesh-ratio R[,R…]] [--motion CLIP …] [--allow-partial] [--unit-scale S] [--asset N]
//  [--json]` (docs/architecture.md sections 6 and 8): a file gets the default LOD set
// (LodSet::fromPixelBudget(asset, 1 pixel, 4 levels)), or with --mesh-ratio LOD0 plus one
// level per ratio with the original motion; each --motion's clips play on the file's
// character through the automatic mapping (ExportJob::motions); a project its own levels,
// joint settings and the motions assigned to its character. The exporter writes through a
// temporary file: an error or Ctrl+C leaves nothing at OUT. Warnings of the exporter (what
// the written file lacks) go to stderr as `warning: OUT: ...`.
// JSON: {"input","plugin","output","ok","message","bytes","levels","options",
//        "seconds":{"import","package","export"}}.
// On a terminal, one stderr line says the stage and its percent while it runs (terminal_progress.h);
// --quiet or --json silence it, and it never appears when stderr is not a terminal.
// Exit 2: bad input (file, project, plugin id, option, level); 1: the export failed
// (unwritable output, cancelled).
struct ExportCommand {
  ExportJob job;                    // the options that map one to one; levels and options below
  std::string levels;               // "0,2,3", parsed into job.levels
  std::vector<std::string> options; // key=value, checked against the plugin into job.options
  std::vector<std::string> meshRatios; // "0.5", "0.25" ..., parsed into job.meshRatios
  bool json = false;
  bool quiet = false; // no progress line on the terminal

  void attach(CLI::App& app);
  int run() const;
};

} // namespace mlod::cli
