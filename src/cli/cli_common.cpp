#include "cli/cli_common.h"

#include "io/isolated_import.h"

#include <CLI/CLI.hpp>

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

void printError(const std::string& file, const std::string& reason) {
  std::cerr << "error: " << file << ": " << reason << std::endl;
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
  Result<Asset> asset = importAssetIsolated(file, options, limits);
  if (!asset) {
    printError(file, asset.message());
    return std::nullopt;
  }
  return std::move(asset).value();
}

} // namespace mlod::cli
