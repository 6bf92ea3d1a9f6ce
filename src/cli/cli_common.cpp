#include "cli/cli_common.h"

#include "core/utf8.h"
#include "io/isolated_import.h"

#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <iostream>

namespace mlod::cli {

void addImportOptions(CLI::App& command, ImportArguments& import) {
  command.add_option("--unit-scale", import.unitScale,
                     "cm per file unit, or a preset: cm, m, mm, inch, cmu (5.6444, CMU mocap); "
                     "default: the file's own unit");
  command.add_option("--fps", import.fps, "resampling rate for formats without a frame rate (not BVH, nor our glTF)")
      ->check(CLI::Range(0.001, 10000.0));
  command.add_option("--import-timeout", import.timeoutSeconds, "seconds before a stuck import is stopped")
      ->check(CLI::Range(1.0, 86400.0));
}

void addProjectOptions(CLI::App& command, ProjectFileOptions& options) {
  command.add_flag("--allow-outside-assets", options.allowOutsideAssets,
                   "follow a project's relative asset paths that leave its folder (../../x.bvh); "
                   "absolute ones are always followed");
}

void addSkinningOption(CLI::App& command, std::optional<LodSkinning>& out, const std::string& what) {
  command
      .add_option_function<std::string>(
          "--skinning", [&out](const std::string& text) { out = lodSkinningFromName(text); },
          what + ": where the character is skinned, gpu (the default: the motion takes half of each level's "
                 "deviation) or cpu (the motion takes its share of the frame cost, pose against CPU skinning)")
      ->type_name("gpu|cpu")
      ->check(CLI::Validator(
          [](std::string& text) {
            return lodSkinningFromName(text) ? std::string()
                                             : "'" + text + "' is neither gpu nor cpu (where the character is skinned)";
          },
          "", "skinning"));
}

namespace {
std::atomic<bool> g_interrupted{false};
volatile std::sig_atomic_t g_signal = 0;

extern "C" void onInterrupt(int signal) {
  g_signal = signal;
  g_interrupted.store(true);
}
} // namespace

const std::atomic<bool>* installInterruptHandler() {
  std::signal(SIGINT, onInterrupt);
  std::signal(SIGTERM, onInterrupt);
  return &g_interrupted;
}

void exitFromInterrupt() {
  const int signal = g_signal != 0 ? int(g_signal) : SIGINT;
  std::signal(signal, SIG_DFL);
  std::raise(signal);
  std::_Exit(128 + signal);
}

namespace {
template <typename Json> std::string jsonTextOf(const Json& doc) {
  try {
    return doc.dump(2);
  } catch (const nlohmann::json::type_error&) {
    std::cerr << "warning: the JSON output names a file whose name is not valid UTF-8; its bad bytes are written as "
                 "U+FFFD"
              << std::endl;
    return doc.dump(2, ' ', false, nlohmann::json::error_handler_t::replace);
  }
}
} // namespace

std::string jsonText(const nlohmann::json& doc) {
  return jsonTextOf(doc);
}
std::string jsonText(const nlohmann::ordered_json& doc) {
  return jsonTextOf(doc);
}

std::string exactNumber(double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

void warnIfNotUtf8(const std::string& file) {
  if (!isValidUtf8(file))
    std::cerr << "warning: " << file << ": the name is not valid UTF-8; the JSON output writes U+FFFD for its bad bytes"
              << std::endl;
}

void printError(const std::string& file, const std::string& reason) {
  std::cerr << "error: " << file << ": " << reason << std::endl;
}

void printWarnings(const std::string& file, const std::vector<std::string>& warnings) {
  for (const std::string& warning : warnings)
    std::cerr << "warning: " << file << ": " << warning << std::endl;
}

std::optional<Asset> importForCommand(const std::string& file, const ImportArguments& arguments) {
  ImportOptions options;
  options.fps = arguments.fps;
  if (!arguments.unitScale.empty()) {
    const std::optional<double> scale = parseUnitScale(arguments.unitScale);
    if (!scale) {
      printError(file, "--unit-scale '" + arguments.unitScale +
                           "' is neither a positive number of cm per unit nor a preset (cm, m, mm, inch, cmu)");
      return std::nullopt;
    }
    options.unitScale = *scale;
  }
  IsolationLimits limits;
  limits.timeoutSeconds = arguments.timeoutSeconds;
  limits.cancel = installInterruptHandler();
  Result<Asset> asset = importAssetIsolated(file, options, limits);
  // what follows the import (clustering, printing) is stopped by Ctrl+C as usual again
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  if (limits.cancel->load()) {
    printError(file, "interrupted: the import was stopped");
    exitFromInterrupt();
  }
  if (!asset) {
    printError(file, asset.message());
    return std::nullopt;
  }
  return std::move(asset).value();
}

} // namespace mlod::cli
