#include "cli/simplify_command.h"

#include "cli/cli_common.h"
#include "core/jpc/jpc.h"
#include "core/jpc/jpc_report.h"
#include "cli/file_checks.h"
#include "core/project.h"

#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <iostream>
#include <sstream>

namespace mlod::cli {

namespace {
std::string defaultAlphaText() {
  char text[32];
  std::snprintf(text, sizeof text, "%g", kDefaultJpcAlpha);
  return text;
}
} // namespace

void SimplifyCommand::attach(CLI::App& app) {
  CLI::App* command = app.add_subcommand(
      "simplify", "Joint posture clustering (JPC) of one clip: simplified joints %, clusters and errors per threshold "
                  "(the paper's Table 1)");
  command
      ->add_option("FILE", file,
                   "motion or character file (any format Assimp reads), or a .mlod project: its asset and clip in "
                   "view, levels, alpha, mode and per-joint settings, unless flags override them")
      ->required();
  command->add_option("--clip", clip, "the clip, by name or index (default: the first)");
  command
      ->add_option("--threshold", thresholds,
                   "error threshold E per LOD level, cm·degrees (E / 57.3 ~ cm), comma-separated: 5,50,100,300 "
                   "(required for a file; a project's default: its levels after the original)")
      ->delimiter(',');
  command->add_option("--alpha", alpha,
                      "orientation weight alpha of every joint, cm, >= 0 (default " + defaultAlphaText() + ")");
  command->add_option("--joint", jointThresholds, "NAME=E: joint NAME's threshold at every level (repeatable)");
  command->add_option("--mode", mode,
                      "greedy: the paper's longest-range-first clusters; optimal: the clusters that cover the most "
                      "frames under the same bound (default greedy)");
  command->add_flag("--json", json,
                    "print one JSON document on stdout (\"joints\" lists the joints with a rotation channel; "
                    "\"seconds\" is clustering and measuring, import excluded)");
  addImportOptions(*command, import);
  addProjectOptions(*command, projectOptions);
  subcommand = command;
}

namespace {

std::string formatNumber(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

// A whole string as a number (NaN and inf included: the checks after name them).
bool parseNumber(const std::string& text, double& out_value) {
  char* end = nullptr;
  out_value = std::strtod(text.c_str(), &end);
  return !text.empty() && end == text.c_str() + text.size();
}

// NAME=E -> (NAME, E); the name may itself hold '='.
bool parseJointThreshold(const std::string& text, std::string& out_name, double& out_threshold) {
  const std::size_t equals = text.rfind('=');
  if (equals == std::string::npos || equals == 0 || equals + 1 == text.size())
    return false;
  out_name = text.substr(0, equals);
  return parseNumber(text.substr(equals + 1), out_threshold);
}

// The clip named `selector`, else the one at index `selector`; -1 when neither.
int findClip(const Asset& asset, const std::string& selector) {
  if (selector.empty())
    return asset.clips.empty() ? -1 : 0;
  for (std::size_t i = 0; i < asset.clips.size(); ++i)
    if (asset.clips[i].name == selector)
      return static_cast<int>(i);
  char* end = nullptr;
  const long index = std::strtol(selector.c_str(), &end, 10);
  if (end == selector.c_str() + selector.size() && index >= 0 && index < static_cast<long>(asset.clips.size()))
    return static_cast<int>(index);
  return -1;
}

void printTable(const JpcReport& report, const Clip& clip, int clusterable) {
  std::printf("file:     %s\n", report.file.c_str());
  std::printf("clip:     %s (%d frames at %g fps), %d of %d joints with a rotation channel\n", report.clip.c_str(),
              report.frames, report.fps, clusterable, clip.jointCount);
  std::printf("settings: mode %s, alpha %g cm, unit %g cm per file unit; E in cm·degrees\n\n", toString(report.mode),
              report.alpha, report.unitScale);
  const auto fixed = [](double value, int digits) {
    char text[64];
    std::snprintf(text, sizeof text, "%.*f", digits, value);
    return std::string(text);
  };
  // One row: a label, the Original column (no simplification: `original`), one per level.
  const auto row = [&](const std::string& label, const std::string& original, auto&& value) {
    std::printf("%-32s %10s", label.c_str(), original.c_str());
    for (const JpcLevelResult& level : report.levels)
      std::printf(" %12s", value(level).c_str());
    std::printf("\n");
  };
  const auto header = [&](const char* first) {
    row(first, "Original", [&](const JpcLevelResult& l) { return "E=" + formatNumber(l.threshold); });
  };
  std::printf("Average simplified joints (%%), as in the paper's Table 1:\n");
  header("Motion");
  row(report.clip, "0.0", [&](const JpcLevelResult& l) { return fixed(l.simplifiedPercent, 1); });
  std::printf("\n");
  row("clusters", "0", [&](const JpcLevelResult& l) { return std::to_string(l.clusterCount); });
  row("max E (cm deg)", "0", [&](const JpcLevelResult& l) { return fixed(l.maxError, 2); });
  row("max joint position error (cm)", "0",
      [&](const JpcLevelResult& l) { return fixed(l.maxJointPositionErrorCm, 3); });
  row("mean joint position error (cm)", "0",
      [&](const JpcLevelResult& l) { return fixed(l.meanJointPositionErrorCm, 3); });
  std::printf("\nPer joint: simplified %% (clusters)\n");
  header("Joint");
  for (std::size_t j = 0; j < report.jointNames.size(); ++j) {
    if (report.levels.empty() || !report.levels.front().joints[j].clusterable)
      continue;
    const std::string name = report.jointNames[j] + (report.levels.front().joints[j].locked ? " (locked)" : "");
    row(name, "0.0", [&](const JpcLevelResult& l) {
      const JointMetrics& m = l.joints[j];
      return fixed(m.simplifiedPercent, 1) + " (" + std::to_string(m.clusters) + ")";
    });
  }
  std::printf("\nseconds:  %.3f (clustering and measuring, import excluded)\n", report.seconds);
}
} // namespace

int SimplifyCommand::run() const {
  const auto flagGiven = [this](const char* name) { return subcommand && subcommand->count(name) > 0; };
  const bool project = isProjectFile(file);
  if (!project && thresholds.empty()) {
    printError(file, "--threshold is required for a file (a .mlod project has its own levels)");
    return kExitBadInput;
  }
  // Arguments that need no file first: a typo costs no import.
  const std::optional<JpcMode> jpcMode = parseJpcMode(mode);
  if (!jpcMode) {
    printError(file, "--mode '" + mode + "' is neither greedy nor optimal");
    return kExitBadInput;
  }
  std::vector<double> levelThresholds;
  for (std::size_t i = 0; i < thresholds.size(); ++i) {
    const std::string what = thresholds.size() == 1 ? "--threshold" : "--threshold entry " + std::to_string(i + 1);
    double value = 0.0;
    if (!parseNumber(thresholds[i], value)) {
      printError(file, what + " '" + thresholds[i] + "' is not a number (cm·degrees)");
      return kExitBadInput;
    }
    if (Error error = validateThreshold(value, what)) {
      printError(file, error.message());
      return kExitBadInput;
    }
    levelThresholds.push_back(value);
  }
  double alphaValue = kDefaultJpcAlpha;
  if (!alpha.empty() && !parseNumber(alpha, alphaValue)) {
    printError(file, "--alpha is '" + alpha + "'; it must be a finite number >= 0 (cm)");
    return kExitBadInput;
  }
  if (Error error = validateAlpha(alphaValue, "--alpha")) {
    printError(file, error.message());
    return kExitBadInput;
  }
  std::vector<std::pair<std::string, double>> jointOverrides; // --joint NAME=E
  for (const std::string& text : jointThresholds) {
    std::string name;
    double threshold = 0.0;
    if (!parseJointThreshold(text, name, threshold)) {
      printError(file, "--joint '" + text + "' is not NAME=E (a joint name and a threshold in cm·degrees)");
      return kExitBadInput;
    }
    jointOverrides.emplace_back(name, threshold);
  }

  // The project, when one is given: which asset, at which unit, with which settings.
  std::optional<Project> loaded;
  std::string assetFile = file;
  ImportArguments importArguments = import;
  int assetIndex = -1;
  if (project) {
    Result<Project> read = loadProjectFile(file, projectOptions);
    if (!read) {
      printError(file, read.message());
      return kExitBadInput;
    }
    loaded = std::move(read).value();
    if (loaded->assets.empty()) {
      printError(file, "the project has no asset to simplify");
      return kExitBadInput;
    }
    assetIndex = loaded->view.asset >= 0 && loaded->view.asset < static_cast<int>(loaded->assets.size())
                     ? loaded->view.asset
                     : 0;
    const ProjectAsset& entry = loaded->assets[static_cast<std::size_t>(assetIndex)];
    assetFile = resolveAssetPath(file, entry.path).string();
    std::error_code error;
    if (!std::filesystem::exists(assetFile, error)) {
      printError(file, "asset " + std::to_string(assetIndex) + " (" + assetFile +
                           ") is missing; relink it in the editor");
      return kExitBadInput;
    }
    if (importArguments.unitScale.empty() && entry.unitScale > 0.0)
      importArguments.unitScale = exactNumber(entry.unitScale);
  }
  const std::optional<Asset> asset = importForCommand(assetFile, importArguments);
  if (!asset)
    return kExitBadInput;
  if (asset->clips.empty()) {
    printError(file, "has no animation clip to simplify");
    return kExitBadInput;
  }
  std::string clipSelector = clip;
  if (loaded && clipSelector.empty() && loaded->view.asset == assetIndex && loaded->view.clip >= 0 &&
      loaded->view.clip < static_cast<int>(asset->clips.size()))
    clipSelector = std::to_string(loaded->view.clip);
  const int clipIndex = findClip(*asset, clipSelector);
  if (clipIndex < 0) {
    std::string names;
    for (const Clip& c : asset->clips)
      names += (names.empty() ? "" : ", ") + c.name;
    printError(file, "no clip '" + clip + "' (by name or index); the file has: " + names);
    return kExitBadInput;
  }
  const Clip& selected = asset->clips[static_cast<std::size_t>(clipIndex)];

  JpcSettings settings;
  if (loaded) {
    // As the editor: the project's alpha, mode and joints (Project::jpcSettings).
    settings = loaded->jpcSettings(assetIndex, asset->unitScale);
    if (levelThresholds.empty()) {
      // The levels after the original, of the asset's own set (lodSetFor()); a joint's
      // override of level i is entry i - 1 here.
      const LodSet& lods = lodSetFor(*loaded, assetIndex);
      for (std::size_t i = 1; i < lods.levels.size(); ++i)
        levelThresholds.push_back(lods.levels[i].motionThreshold);
      for (auto& [name, joint] : settings.joints)
        if (!joint.thresholds.empty())
          joint.thresholds.erase(joint.thresholds.begin());
      if (levelThresholds.empty()) {
        printError(file, "the project has no LOD level beyond the original; give --threshold");
        return kExitBadInput;
      }
    } else {
      for (auto& [name, joint] : settings.joints) // other levels: the overrides do not apply
        joint.thresholds.clear();
    }
  }
  settings.zeroLength = 1e-6 * asset->unitScale; // docs/architecture.md: 1e-6 file units
  if (!loaded || flagGiven("--mode"))
    settings.mode = *jpcMode;
  if (!loaded || flagGiven("--alpha"))
    settings.alpha = alphaValue;
  for (const auto& [name, threshold] : jointOverrides)
    settings.joints[name].thresholds.assign(levelThresholds.size(), threshold);

  const auto start = std::chrono::steady_clock::now();
  Result<std::vector<JpcLevelResult>> levels = simplifyClip(asset->skeleton, selected, settings, levelThresholds);
  if (!levels) {
    printError(file, levels.message());
    return kExitBadInput;
  }
  JpcReport report;
  report.file = file;
  report.clip = selected.name;
  report.frames = selected.frameCount;
  report.fps = selected.fps;
  report.mode = settings.mode;
  report.alpha = settings.alpha;
  report.unitScale = asset->unitScale;
  for (const Joint& joint : asset->skeleton.joints)
    report.jointNames.push_back(joint.name);
  report.levels = std::move(levels).value();
  report.seconds = secondsSince(start);
  if (json) {
    warnIfNotUtf8(file);
    std::cout << jpcReportJson(report) << std::endl;
  } else
    printTable(report, selected, selected.rotationChannelCount());
  return kExitOk;
}

} // namespace mlod::cli
