#pragma once

#include "cli/cli_common.h"

#include <string>

namespace CLI { class App; }

namespace mlod::cli {

// `motionlod batch MANIFEST.json [--shard I/N] [--jobs K] [--json]` (docs/architecture.md section 6):
// exports many assets. The manifest is
//     {"jobs":[{"input","plugin","output","options":{},   ("levels":[0,2], "unit_scale":S optional)}]}
// with paths relative to the manifest's folder. --shard I/N takes the jobs whose index is
// I mod N, so a farm scheduler splits a library over N machines by running shard 0 .. N-1;
// --jobs K runs K jobs at once on this machine. Each job's output depends on its input
// alone (never on the shard or K). Prints what each job did, in job order; JSON:
// {"manifest","shard":{"index","count"},"jobs":[{"index","input","plugin","output","ok",
//  "exit","message","bytes","seconds"}],"succeeded","failed","seconds"}.
// On a terminal, one stderr line says how many jobs are done and where the latest report
// came from (terminal_progress.h); --quiet or --json silence it.
// Before any job runs, over the whole manifest (whatever the shard): a manifest that is no
// regular file of at most 64 MiB, or a job that would write the manifest, an input of any
// job (by file identity), an existing file that is not a regular one, or the same file as
// another job is refused (exit 2). An output outside the manifest's folder is written with
// a warning (--allow-outside: none).
// Exit: 2 for a bad manifest or arguments (nothing runs); else 0 when every job of the
// shard succeeded, or the exit status of the first job that failed (2 bad input, 1 other:
// a missing or read-only output folder is 1, so a farm retries it).
struct BatchCommand {
  std::string manifest;
  std::string shard = "0/1";
  int jobs = 1;
  bool json = false;
  bool quiet = false; // no progress line on the terminal
  bool allowOutside = false; // no warning for outputs outside the manifest's folder
  ProjectFileOptions project; // where the projects' assets may be (every job)

  void attach(CLI::App& app);
  int run() const;
};

} // namespace mlod::cli
