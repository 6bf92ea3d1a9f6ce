#pragma once

#include "cli/cli_common.h"

#include <string>

namespace CLI { class App; }

namespace mlod::cli {

// `motionlod bench-crowd FILE --characters N --frames F --threshold E [--alpha A]
//  [--unit-scale S] [--threads K] [--json]` (docs/architecture.md sections 5, 6): what the motion LOD
// buys at run time. One process builds a crowd of N characters playing the file's first
// clip (looping, each starting at its own time, advancing 1/60 s per frame) and evaluates
// the same F frames at full detail (the same job on a clip without clusters) and at the
// LOD of threshold E, alternating full and LOD repetitions; figures are medians. Both
// produce model matrices and the skinning palette; where the file has a skinned mesh,
// every character is skinned too, timed on its own and in the totals.
struct BenchCrowdCommand {
  std::string file;
  int characters = 1000;
  int frames = 100;
  double threshold = 50.0; // cm·degrees
  double alpha = 5.0;      // cm
  int threads = 1;
  int blendFrames = 4;     // unfreeze blending, frames (0 = off)
  int repetitions = 5;     // of each of full and LOD, after one warm-up of each
  bool paletteOnly = false;
  std::string only;        // "", "full" or "lod": run one side only (for callgrind)
  bool json = false;
  ImportArguments import;

  void attach(CLI::App& app);
  int run() const;
};

} // namespace mlod::cli
