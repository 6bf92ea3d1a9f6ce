#include "cli/export_command.h"

#include "cli/export_job.h"
#include "cli/terminal_progress.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>

namespace mlod::cli {

void ExportCommand::attach(CLI::App& app) {
  CLI::App* command = app.add_subcommand("export", "Export a file's or a project's LOD set through an exporter plugin");
  command->add_option("FILE", job.input, "character or motion file (any format Assimp reads), or a .mlod project")
      ->required();
  command->add_option("--plugin", job.plugin, "exporter id (motionlod plugins lists them)")->required();
  command->add_option("-o,--output", job.output, "output file")->required();
  command->add_option("--levels", levels, "levels to export by index, e.g. 0,2,3 (default: all)");
  command->add_option("--option", options, "exporter option key=value (repeatable; motionlod plugins lists them)");
  command->add_option("--mesh-ratio", meshRatios,
                      "instead of the default LOD set: LOD0 plus one level per triangle ratio in (0, 1], "
                      "comma-separated (0.5,0.25,0.1), each with the original motion (a file only)")
      ->delimiter(',');
  addSkinningOption(*command, job.skinning, "for a file's default LOD set (a file only)");
  command->add_option("--motion", job.motions,
                      "a motion file whose clips play on FILE's character, mapped by joint names (the automatic "
                      "motion mapping, as bench-crowd --scene --motion); repeatable; a file only");
  command->add_flag("--allow-partial", job.allowPartial,
                    "export a --motion whose mapping drives less than half of the character's joints with a child");
  command->add_option("--unit-scale", job.unitScale,
                      "cm per file unit, or a preset: cm, m, mm, inch, cmu (5.6444, CMU mocap); "
                      "default: the file's own unit (a project: each asset's)");
  command->add_option("--asset", job.asset, "a project's asset to export, by index (default: its character)");
  command->add_option("--character", job.character,
                      "a project's character to export with its own LOD set and the motions mapped onto it: its "
                      "file name (BCN_Epileptic.X), path or index (default: the character of the asset in view)");
  command->add_option("--import-timeout", job.importTimeoutSeconds, "seconds before a stuck import is stopped")
      ->check(CLI::Range(1.0, 86400.0));
  addProjectOptions(*command, job.project);
  command->add_flag("--json", json, "print one JSON document on stdout");
  command->add_flag("-q,--quiet", quiet, "no progress line on the terminal (stderr)");
}

int ExportCommand::run() const {
  ExportJob filled = job; // levels and options are filled in below
  const std::string& input = job.input;
  const std::string& plugin = job.plugin;
  std::string reason;
  if (!levels.empty() && !parseLevelList(levels, filled.levels, reason)) {
    printError(input, reason);
    return kExitBadInput;
  }
  for (const std::string& text : meshRatios) {
    char* end = nullptr;
    const double ratio = std::strtod(text.c_str(), &end);
    if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(ratio) || !(ratio > 0.0 && ratio <= 1.0)) {
      printError(input, "--mesh-ratio '" + text + "': a triangle ratio must be a number in (0, 1]");
      return kExitBadInput;
    }
    filled.meshRatios.push_back(ratio);
  }
  PluginHost host;
  host.loadDefault();
  // --option strings are parsed against the plugin's options (typed, ranges, choices)
  if (Exporter* exporter = host.exporter(QString::fromStdString(plugin))) {
    QStringList keyValues;
    for (const std::string& option : options)
      keyValues << QString::fromStdString(option);
    QString error;
    if (!parseExporterOptions(exporter->options(), keyValues, &filled.options, &error)) {
      printError(input, "plugin " + plugin + ": " + error.toStdString());
      return kExitBadInput;
    }
  }
  TerminalProgress line(!quiet && !json);
  const ExportOutcome outcome = runExportJob(
      host, filled, installInterruptHandler(),
      [&](std::string_view stage, double fraction, std::string_view detail) { line.show(stage, fraction, detail); });
  line.clear();
  if (!outcome.ok())
    printError(outcome.errorFile, outcome.message);
  printWarnings(job.output, outcome.warnings);
  if (json) {
    nlohmann::json options_json = nlohmann::json::object();
    for (auto it = filled.options.begin(); it != filled.options.end(); ++it)
      options_json[it.key().toStdString()] = it.value().toString().toStdString();
    nlohmann::json doc = {{"input", input},
                          {"plugin", plugin},
                          {"output", job.output},
                          {"ok", outcome.ok()},
                          {"message", outcome.message},
                          {"bytes", outcome.bytes},
                          {"levels", outcome.levels},
                          {"options", options_json},
                          {"seconds",
                           {{"import", outcome.importSeconds},
                            {"package", outcome.packageSeconds},
                            {"export", outcome.exportSeconds}}}};
    if (!outcome.character.empty()) // a project's: the character exported
      doc["character"] = outcome.character;
    std::cout << jsonText(doc) << std::endl;
  } else if (outcome.ok()) {
    std::printf("%s\n%d levels; import %.3f s, LOD package %.3f s, export %.3f s\n", outcome.message.c_str(),
                outcome.levels, outcome.importSeconds, outcome.packageSeconds, outcome.exportSeconds);
  }
  return outcome.exitCode;
}

} // namespace mlod::cli
