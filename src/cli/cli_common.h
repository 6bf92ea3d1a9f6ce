#pragma once
// What every motionlod command shares: exit codes, error printing, importing a file.

#include "core/asset.h"
#include "core/project.h"
#include "io/import_options.h"

#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace CLI { class App; }

namespace mlod::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;  // something other than the input went wrong
inline constexpr int kExitBadInput = 2; // the input (file or arguments) is bad

// Seconds on the steady clock since `start`, for the timings commands print.
inline double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Prints "error: FILE: reason" on stderr.
void printError(const std::string& file, const std::string& reason);
// `warning: FILE: warning` on stderr, one line each.
void printWarnings(const std::string& file, const std::vector<std::string>& warnings);

// The JSON text of `doc` (indent 2), never an exception: strings that are not valid UTF-8
// (file names are kept as bytes; names from files are made valid on import) are written
// with U+FFFD for their bad bytes, and a warning on stderr says so.
std::string jsonText(const nlohmann::json& doc);
std::string jsonText(const nlohmann::ordered_json& doc);

// A number as text that parses back to the same double ("%.17g").
std::string exactNumber(double value);

// Warns on stderr when `file` is not valid UTF-8: JSON written from it holds U+FFFD instead.
void warnIfNotUtf8(const std::string& file);

// How long a command waits for the import worker by default (--import-timeout): a file
// that makes an Assimp parser loop for ever (a truncated SMD) is an error within the
// minute any command is given (issue 29); the largest inputs the limits allow import in
// a fraction of it (a 100 MB BVH: 11 s on a loaded machine).
inline constexpr double kDefaultImportTimeoutSeconds = 45.0;

// Import options as the commands take them.
struct ImportArguments {
  std::string unitScale;        // "" = the file's own; a number or a preset name
  double fps = 30.0;
  double timeoutSeconds = kDefaultImportTimeoutSeconds;
};

// Adds --unit-scale, --fps and --import-timeout to a command.
void addImportOptions(CLI::App& command, ImportArguments& import);

// Adds --allow-outside-assets to a command that reads projects: their relative asset paths
// may then leave the project's folder (core/project.h, ProjectFileOptions).
void addProjectOptions(CLI::App& command, ProjectFileOptions& options);

// `--skinning cpu|gpu` (LodBudgetOptions::skinning): where the character of a generated LOD
// set is skinned. Any other value is a parse error naming the two (exit 2); `out` stays
// unset when the option is not given. `what` starts the help line (which set it applies to).
void addSkinningOption(CLI::App& command, std::optional<LodSkinning>& out, const std::string& what);

// Makes SIGINT and SIGTERM (Ctrl+C, a farm scheduler stopping the job) set the returned
// flag instead of killing the process, so that a running export stops and leaves nothing
// and a running import stops its worker at once.
const std::atomic<bool>* installInterruptHandler();

// Ends the process by the signal that set the interrupt flag (the shell then sees 130 for
// Ctrl+C), once what it interrupted has been cleaned up.
[[noreturn]] void exitFromInterrupt();

// Imports `file` in a sandboxed worker; prints the error and returns nothing on failure.
// Ctrl+C (or SIGTERM) stops the worker at once and ends the process (exitFromInterrupt()).
std::optional<Asset> importForCommand(const std::string& file, const ImportArguments& arguments);

} // namespace mlod::cli
