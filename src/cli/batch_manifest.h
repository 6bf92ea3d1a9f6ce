#pragma once
// The batch manifest of `motionlod batch` (docs/architecture.md section 6), parsed and checked
// without Qt, so the sanitizer build fuzzes it (tests/fuzz/manifest_fuzzer.cpp):
//     {"jobs":[{"input","plugin","output","options":{},
//               ("levels":[0,2], "unit_scale":S, "character":C, "skinning":"gpu"|"cpu" optional)}]}
// Paths are relative to the manifest's folder. Errors name the job and the key.

#include "core/error.h"
#include "core/lod/lod_set.h"

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mlod::cli {

struct ManifestJob {
  std::string input; // resolved against the manifest's folder, lexically normal
  std::string plugin;
  std::string output;                                // resolved as the input
  nlohmann::json options = nlohmann::json::object(); // key -> bool, number or string
  std::vector<int> levels;                           // empty = every level
  std::string unitScale;                             // "" = the file's own; else a positive number or a preset name
  std::string character; // a project's character to export (export --character): file name, path or index; "" = default
  std::optional<LodSkinning> skinning; // a file's default LOD set (export --skinning); unset = the GPU
};

// The jobs of a manifest whose text is `text` and whose folder is `folder`. Errors: not JSON,
// not {"jobs":[...]}, a job without "input", "plugin" or "output" (non-empty strings), an
// unknown key, options that are not bool, number or string, levels that are not indices,
// a unit scale that is neither a positive number nor a preset (cm, m, mm, inch, cmu), a
// character that is neither a non-empty string nor an index, a skinning other than "gpu" or "cpu".
Result<std::vector<ManifestJob>> parseBatchManifest(std::string_view text, const std::filesystem::path& folder);

} // namespace mlod::cli
