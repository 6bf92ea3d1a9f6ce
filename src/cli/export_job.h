#pragma once
// One export as `motionlod export` and each job of `motionlod batch` run it (docs/architecture.md
// sections 6 and 8): import the file (or a project's character and the motions assigned to
// it), build the LodPackage of the selected levels, and hand it to an exporter plugin.
// Nothing is printed here: the outcome says what happened, so the batch can run jobs on
// several threads and report them in order.

#include "cli/cli_common.h"
#include "sdk/plugin_host.h"

#include <QStringList>
#include <QVariantMap>

#include <atomic>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mlod::cli {

struct ExportJob {
  std::string input;  // a file any importer reads, or a .mlod project
  std::string plugin; // exporter id
  std::string output;
  std::vector<int> levels;   // empty = every level
  QVariantMap options;       // checked against the plugin's options (checkExporterOptions())
  std::string unitScale;     // "" = the file's own (a project: each asset's own)
  int asset = -1;            // a project's asset to export; -1 = `character`, else its character in view
  // A project's character to export with its own set and the motions mapped onto it, by file
  // name, path or index (core/project_package.h's exportCharacterNamed()); "" = as `asset` says.
  std::string character;
  double importTimeoutSeconds = kDefaultImportTimeoutSeconds;
  ProjectFileOptions project; // where a project's assets may be
  // A file's levels by mesh ratio alone (each in (0, 1]): LOD0 plus one level per ratio with
  // the original motion (threshold 0), so a mesh can be judged alone; empty = the default
  // LOD set. Not for a project (its levels are its own).
  std::vector<double> meshRatios;
  // Where a file's character is skinned, for its default LOD set (LodBudgetOptions::skinning;
  // unset: the GPU). Not for a project (its set's own) nor with meshRatios.
  std::optional<LodSkinning> skinning;
  // Motion files whose clips play on the file's character (a file only; a project plays the
  // motions its mappings assign), each mapped by the automatic mapping
  // (mapMotionAutomatically(), as bench-crowd --scene --motion), at its own unit. A motion
  // whose mapping drives less than kMinMappedShare of the character's joints with a child is
  // refused (exit 2) unless `allowPartial`.
  std::vector<std::string> motions;
  bool allowPartial = false;
};

struct ExportOutcome {
  int exitCode = kExitOk;
  std::string message; // what was written, or why nothing was (without "error: FILE: ")
  std::vector<std::string> warnings; // what the written file lacks (the exporter's warning lines), one sentence each
  std::string errorFile; // the file the error is about (the input, the output, the plugin id)
  std::string character; // a project's: the file name of the character exported; else empty
  std::int64_t bytes = 0; // the output file's size (0 when nothing was written)
  double importSeconds = 0.0;
  double packageSeconds = 0.0;
  double exportSeconds = 0.0;
  int levels = 0;
  bool ok() const { return exitCode == kExitOk; }
};

// "0,2,3" -> {0, 2, 3}; false (and a reason) on anything else.
bool parseLevelList(const std::string& text, std::vector<int>& out_levels, std::string& out_reason);

// Where a running job is: stage "import", "LOD package" or "export", the stage's fraction in
// [0, 1] (< 0 where the stage has no measure: the import) and what the step is doing, as the
// package build and the exporter plugin report it. Called on the job's thread.
using ExportJobProgress = std::function<void(std::string_view stage, double fraction, std::string_view detail)>;

// Empty when `output` ends in one of the suffixes of the plugin `plugin`'s metadata (or the
// host has no such plugin: runExportJob() says so), else why not, as the Export dialog refuses
// it: "the gltf exporter writes .glb or .gltf files, not .bundle". The file's suffix says its
// format; checked before any work, by export and by batch over the whole manifest.
std::string outputSuffixProblem(const PluginHost& host, const std::string& plugin, const std::string& output);

// Runs one job with the exporters of `host`. `cancel` (may be null) stops it between steps
// and inside the package build and the exporter; a cancelled job writes nothing. `progress`
// may be empty.
ExportOutcome runExportJob(const PluginHost& host, const ExportJob& job, const std::atomic<bool>* cancel = nullptr,
                           const ExportJobProgress& progress = {});

} // namespace mlod::cli
