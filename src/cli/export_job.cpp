#include "cli/export_job.h"

#include "core/lod/lod_package.h"
#include "core/project.h"
#include "io/import_options.h"
#include "io/isolated_import.h"

#include <QDir>
#include <QFileInfo>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <memory>
#include <sstream>

namespace mlod::cli {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

bool isProjectFile(const std::string& file) {
  return file.size() >= 5 && file.compare(file.size() - 5, 5, ".mlod") == 0;
}

ExportOutcome failure(int code, std::string file, std::string message) {
  ExportOutcome out;
  out.exitCode = code;
  out.errorFile = std::move(file);
  out.message = std::move(message);
  return out;
}

Result<Asset> importFile(const std::string& path, double unitScale, const ExportJob& job,
                         const std::atomic<bool>* cancel) {
  ImportOptions options;
  options.unitScale = unitScale;
  IsolationLimits limits;
  limits.timeoutSeconds = job.importTimeoutSeconds;
  limits.cancel = cancel;
  return importAssetIsolated(path, options, limits);
}

std::atomic<bool> g_interrupted{false};

extern "C" void onInterrupt(int) {
  g_interrupted.store(true);
}

} // namespace

const std::atomic<bool>* installInterruptHandler() {
  std::signal(SIGINT, onInterrupt);
  std::signal(SIGTERM, onInterrupt);
  return &g_interrupted;
}

bool parseLevelList(const std::string& text, std::vector<int>& out_levels, std::string& out_reason) {
  out_levels.clear();
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    std::size_t used = 0;
    int value = -1;
    try {
      value = std::stoi(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size() || value < 0) {
      out_reason = "--levels '" + text + "': '" + item + "' is not a level index (0, 1, 2 ...)";
      return false;
    }
    out_levels.push_back(value);
  }
  if (out_levels.empty()) {
    out_reason = "--levels is empty";
    return false;
  }
  return true;
}

ExportOutcome runExportJob(const PluginHost& host, const ExportJob& job, const std::atomic<bool>* cancel,
                           const ExportJobProgress& report) {
  const auto cancelled = [cancel] { return cancel && cancel->load(); };
  // What needs no import first: a typo costs nothing.
  Exporter* exporter = host.exporter(QString::fromStdString(job.plugin));
  if (!exporter) {
    QStringList ids;
    for (const PluginInfo& info : host.plugins())
      ids << info.id;
    return failure(kExitBadInput, job.input,
                   "no exporter plugin '" + job.plugin + "' (available: " +
                       (ids.isEmpty() ? std::string("none; see motionlod plugins") : ids.join(", ").toStdString()) + ")");
  }
  QVariantMap options;
  QString optionError;
  if (!checkExporterOptions(exporter->options(), job.options, &options, &optionError))
    return failure(kExitBadInput, job.input, "plugin " + job.plugin + ": " + optionError.toStdString());
  if (job.output.empty())
    return failure(kExitBadInput, job.input, "no output file (-o)");
  const QFileInfo output(QString::fromStdString(job.output));
  const QFileInfo folder(output.absolutePath());
  if (!folder.isDir())
    return failure(kExitFailure, job.output, "cannot write: the folder " + folder.filePath().toStdString() + " does not exist");
  if (!folder.isWritable())
    return failure(kExitFailure, job.output, "cannot write: the folder " + folder.filePath().toStdString() + " is not writable");
  if (output.isDir())
    return failure(kExitFailure, job.output, "cannot write: it is a folder");
  double unitScale = 0.0;
  if (!job.unitScale.empty()) {
    const std::optional<double> scale = parseUnitScale(job.unitScale);
    if (!scale)
      return failure(kExitBadInput, job.input,
                     "--unit-scale '" + job.unitScale +
                         "' is neither a positive number of cm per unit nor a preset (cm, m, mm, inch, cmu)");
    unitScale = *scale;
  }

  ExportOutcome out;
  const auto tell = [&](std::string_view stage, double fraction, std::string_view detail) {
    if (report)
      report(stage, fraction, detail);
  };
  const LodPackageProgress progress = [&](double fraction, std::string_view detail) {
    tell("LOD package", fraction, detail);
    return !cancelled();
  };
  tell("import", -1.0, job.input);
  Result<LodPackage> package = Error("no package");
  Clock::time_point start = Clock::now();
  if (isProjectFile(job.input)) {
    Result<Project> project = loadProjectFile(job.input);
    if (!project)
      return failure(kExitBadInput, job.input, project.message());
    const int assets = static_cast<int>(project->assets.size());
    if (assets == 0)
      return failure(kExitBadInput, job.input, "the project has no asset to export");
    if (job.asset >= assets)
      return failure(kExitBadInput, job.input, "the project has no asset " + std::to_string(job.asset));
    // which assets to import: the character and every motion assigned to it
    std::vector<std::unique_ptr<Asset>> owned(static_cast<std::size_t>(assets));
    std::vector<const Asset*> imported(std::size_t(assets), nullptr);
    const auto importAt = [&](int a) -> std::optional<ExportOutcome> {
      if (imported[std::size_t(a)])
        return std::nullopt;
      const ProjectAsset& entry = project->assets[std::size_t(a)];
      const std::string path = resolveAssetPath(job.input, entry.path).string();
      std::error_code error;
      if (!std::filesystem::exists(path, error))
        return failure(kExitBadInput, job.input, "asset " + std::to_string(a) + " (" + path + ") is missing; relink it in the editor");
      Result<Asset> asset = importFile(path, unitScale > 0.0 ? unitScale : entry.unitScale, job, cancel);
      if (!asset)
        return failure(cancelled() ? kExitFailure : kExitBadInput, path, cancelled() ? "cancelled" : asset.message());
      owned[std::size_t(a)] = std::make_unique<Asset>(std::move(asset).value());
      imported[std::size_t(a)] = owned[std::size_t(a)].get();
      return std::nullopt;
    };
    int character = job.asset;
    if (character < 0) {
      const int view = project->view.asset;
      bool viewIsMotion = false;
      for (const ProjectMapping& mapping : project->mappings)
        viewIsMotion = viewIsMotion || mapping.motion == view;
      character = view >= 0 && view < assets && !viewIsMotion ? view : -1;
    }
    if (character < 0) {
      // the character of a mapping, else the first asset with a skinned mesh, else the first
      // (defaultPackageAsset() on what is imported: import the candidates first)
      for (const ProjectMapping& mapping : project->mappings)
        if (std::optional<ExportOutcome> failed = importAt(mapping.character))
          return *failed;
      if (project->mappings.empty())
        for (int a = 0; a < assets; ++a)
          if (std::optional<ExportOutcome> failed = importAt(a))
            return *failed;
      character = defaultPackageAsset(*project, imported);
    }
    if (std::optional<ExportOutcome> failed = importAt(character))
      return *failed;
    for (const ProjectMapping& mapping : project->mappings)
      if (mapping.character == character)
        if (std::optional<ExportOutcome> failed = importAt(mapping.motion))
          return *failed;
    out.importSeconds = secondsSince(start);
    start = Clock::now();
    package = buildLodPackage(*project, imported, character, job.levels, progress);
  } else {
    Result<Asset> asset = importFile(job.input, unitScale, job, cancel);
    if (!asset)
      return failure(cancelled() ? kExitFailure : kExitBadInput, job.input, cancelled() ? "cancelled" : asset.message());
    out.importSeconds = secondsSince(start);
    start = Clock::now();
    package = buildLodPackage(*asset, job.levels, progress);
  }
  if (!package) {
    if (package.message() == kLodPackageCancelled)
      return failure(kExitFailure, job.input, "cancelled: nothing was written");
    return failure(kExitBadInput, job.input, package.message());
  }
  out.packageSeconds = secondsSince(start);
  out.levels = static_cast<int>(package->levels.size());
  if (cancelled())
    return failure(kExitFailure, job.input, "cancelled: nothing was written");

  start = Clock::now();
  const QString path = QString::fromStdString(job.output);
  tell("export", 0.0, job.plugin);
  const ExportResult result = exporter->exportPackage(
      *package, path, options,
      ExportProgress([&](double fraction, const QString& detail) { tell("export", fraction, detail.toStdString()); },
                     [&] { return cancelled(); }));
  out.exportSeconds = secondsSince(start);
  if (!result.ok) {
    std::string message = result.message.toStdString();
    if (message.rfind(job.output + ": ", 0) == 0) // the exporter named the output already
      message.erase(0, job.output.size() + 2);
    ExportOutcome failed = failure(kExitFailure, job.output, message);
    failed.importSeconds = out.importSeconds;
    failed.packageSeconds = out.packageSeconds;
    failed.exportSeconds = out.exportSeconds;
    return failed;
  }
  out.message = result.message.toStdString();
  out.bytes = QFileInfo(path).size();
  return out;
}

} // namespace mlod::cli
