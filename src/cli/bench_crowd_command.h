#pragma once

#include "cli/cli_common.h"
#include "core/jpc/jpc_settings.h"
#include "core/lod/lod_set.h"

#include <optional>
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
// every character is skinned too (unless `noSkinning`), timed on its own and in the totals.
// Each side reports its clip_bytes (LodClip::byteSize() of every clip its evaluator reads,
// each once) and bytes_per_second (clip_bytes over the clip's duration, LodClip::duration()).
struct BenchCrowdCommand {
  std::string file;
  int characters = 1000;
  int frames = 100;
  std::optional<double> threshold; // cm·degrees; required without --scene
  double alpha = kDefaultJpcAlpha; // cm
  int threads = 1;
  int blendFrames = 4; // unfreeze blending, frames (0 = off)
  int repetitions = 5; // of each of full and LOD, after one warm-up of each
  bool paletteOnly = false;
  std::string only; // "", "full" or "lod": run one side only (for callgrind)
  bool json = false;
  ImportArguments import;
  // --scene (docs/architecture.md section 6; the paper's Figure 12): FILE is a character with
  // a skinned mesh; a crowd of `agents` plays its clip (or `motion`, mapped onto it) at the
  // levels of LodSet::fromPixelBudget(budgetPixels, levelCount), each agent at the level of
  // its distance to a camera at the crowd's front (with hysteresis), and every frame is
  // pose evaluation plus CPU skinning of every agent, in four configurations: none (every
  // agent at level 0), skeletal (the levels' motion, level 0's mesh), mesh (level 0's
  // motion, the levels' meshes) and both. Each configuration reports its clip bytes as a
  // side does, and each level its agent cost: the frame time of the crowd of "both" with
  // every agent forced to that level over the same with every agent at level 0 (timed in
  // the same run, the levels alternating within each repetition).
  bool scene = false;
  std::string motion;
  int agents = 1000;
  double budgetPixels = 1.0;
  int levelCount = 4;
  std::string layout = "grid";
  std::optional<LodSkinning> budgetSkinning; // --scene: where the generated set's character is skinned; unset: the GPU
  bool noSkinning = false; // skin nothing: the pose alone, what an engine's CPU pays when the GPU skins

  void attach(CLI::App& app);
  int run() const;
  int runScene() const;
};

} // namespace mlod::cli
