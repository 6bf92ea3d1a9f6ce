#include "cli/export_job.h"

#include "cli/cli_common.h"
#include "cli/file_checks.h"

#include "core/mapping/motion_mapping.h"
#include "core/project_package.h"
#include "core/project.h"
#include "io/import_options.h"
#include "io/isolated_import.h"

#include <QFile>
#include <QFileInfo>

#include <cerrno>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fcntl.h>
#include <optional>
#include <unistd.h>
#include <csignal>
#include <filesystem>
#include <memory>
#include <span>
#include <sstream>

namespace mlod::cli {

namespace {

using Clock = std::chrono::steady_clock;

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

// An output whose name is not valid UTF-8 (a Latin-1 name): Qt paths are Unicode, so an
// exporter given QString::fromStdString() of it would write a file named with U+FFFD and
// report success. Instead the exporter writes into a fresh folder beside the output
// (reached through /proc/self/fd, so the folder's own name may hold any bytes), under the
// name decoded with U+FFFD; commit() then renames every file it wrote to the exact bytes
// given (FILE.mlodb.json follows FILE.mlodb). On failure or without commit() nothing stays.
class ByteExactOutput {
public:
  ByteExactOutput() = default;
  ByteExactOutput(const ByteExactOutput&) = delete;
  ByteExactOutput& operator=(const ByteExactOutput&) = delete;
  ~ByteExactOutput() { discard(); }

  bool open(const std::string& output, QString* out_path, std::string* out_reason) {
    const std::filesystem::path file(output);
    const std::string folder = file.has_parent_path() ? file.parent_path().string() : std::string(".");
    m_name = file.filename().string();
    m_folder = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (m_folder < 0)
      return fail(out_reason);
    std::string scratch = "/proc/self/fd/" + std::to_string(m_folder) + "/.motionlod-export-XXXXXX";
    if (!::mkdtemp(scratch.data()))
      return fail(out_reason);
    m_scratch = std::filesystem::path(scratch).filename().string();
    m_decoded = QFile::encodeName(QFile::decodeName(QByteArray::fromStdString(m_name))).toStdString();
    *out_path = QStringLiteral("/proc/self/fd/%1/%2/").arg(m_folder).arg(QString::fromStdString(m_scratch)) +
                QFile::decodeName(QByteArray::fromStdString(m_name));
    return true;
  }

  bool commit(std::string* out_reason) {
    for (const std::string& written : scratchFiles()) {
      const std::string target =
          written.rfind(m_decoded, 0) == 0 ? m_name + written.substr(m_decoded.size()) : written;
      if (::renameat(m_folder, (m_scratch + "/" + written).c_str(), m_folder, target.c_str()) != 0)
        return fail(out_reason);
    }
    return true;
  }

private:
  std::vector<std::string> scratchFiles() const {
    std::vector<std::string> names;
    std::error_code error;
    for (const auto& entry : std::filesystem::directory_iterator(
             "/proc/self/fd/" + std::to_string(m_folder) + "/" + m_scratch, error))
      names.push_back(entry.path().filename().string());
    return names;
  }
  void discard() {
    if (m_folder < 0)
      return;
    if (!m_scratch.empty()) {
      for (const std::string& left : scratchFiles())
        ::unlinkat(m_folder, (m_scratch + "/" + left).c_str(), 0);
      ::unlinkat(m_folder, m_scratch.c_str(), AT_REMOVEDIR);
    }
    ::close(m_folder);
    m_folder = -1;
  }
  static bool fail(std::string* out_reason) {
    *out_reason = std::strerror(errno);
    return false;
  }

  int m_folder = -1;
  std::string m_name;    // the output's file name, exact bytes
  std::string m_decoded; // what Qt writes for it (U+FFFD for each invalid byte), as bytes
  std::string m_scratch; // the scratch folder's name inside the output's folder
};

} // namespace

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

std::string outputSuffixProblem(const PluginHost& host, const std::string& plugin, const std::string& output) {
  const QString id = QString::fromStdString(plugin);
  for (const PluginInfo& info : host.plugins()) {
    if (info.id != id)
      continue;
    const QString path = QString::fromStdString(output); // a Latin-1 name's suffix is still ASCII
    if (hasSuffix(path, info.suffixes))
      return {};
    const QString suffix = QFileInfo(path).suffix();
    return "the " + plugin + " exporter writes " + suffixesText(info.suffixes).toStdString() + " files" +
           (suffix.isEmpty() ? std::string(", and the name has no suffix") : ", not ." + suffix.toStdString());
  }
  return {};
}

namespace {

// One export job as its steps share it: check, import and build, write.
struct JobRun {
  const PluginHost& host;
  const ExportJob& job;
  const std::atomic<bool>* cancel;
  const ExportJobProgress& report;
  Exporter* exporter = nullptr;
  QVariantMap options; // every option of the exporter, checked
  double unitScale = 0.0; // --unit-scale; 0 = each file's own
  ExportOutcome out;      // the timings so far
  std::vector<std::string> notes; // lines that go before the exporter's message (the motions mapped)

  bool cancelled() const { return cancel && cancel->load(); }
  void tell(std::string_view stage, double fraction, std::string_view detail) const {
    if (report)
      report(stage, fraction, detail);
  }
  LodPackageProgress packageProgress() const {
    return [this](double fraction, std::string_view detail) {
      tell("LOD package", fraction, detail);
      return !cancelled();
    };
  }
  // A failed import: bad input, unless the user stopped it.
  ExportOutcome importFailure(const std::string& file, const std::string& message) const {
    return cancelled() ? failure(kExitFailure, file, "cancelled") : failure(kExitBadInput, file, message);
  }
};

// 1. What needs no import (a typo costs nothing): the plugin and its options, the outputs
// (nothing lost), their folder, the unit, the mesh ratios.
std::optional<ExportOutcome> checkJob(JobRun& run) {
  const ExportJob& job = run.job;
  run.exporter = run.host.exporter(QString::fromStdString(job.plugin));
  if (!run.exporter) {
    QStringList ids;
    for (const PluginInfo& info : run.host.plugins())
      ids << info.id;
    return failure(kExitBadInput, job.input,
                   "no exporter plugin '" + job.plugin + "' (available: " +
                       (ids.isEmpty() ? std::string("none; see motionlod plugins") : ids.join(", ").toStdString()) + ")");
  }
  QString optionError;
  if (!checkExporterOptions(run.exporter->options(), job.options, &run.options, &optionError))
    return failure(kExitBadInput, job.input, "plugin " + job.plugin + ": " + optionError.toStdString());
  if (job.output.empty())
    return failure(kExitBadInput, job.input, "no output file (-o)");
  // Nothing lost: no output may be an input, and what exists at an output must be a
  // regular file (file_checks.h). Checked before any work.
  const std::vector<std::string> inputs = exportInputFiles(job.input);
  for (const std::string& file : exportOutputFiles(job.plugin, job.output, run.options))
    if (std::string problem = outputProblem(file, inputs); !problem.empty())
      return failure(kExitBadInput, file, problem);
  // the output's suffix says its format (as the Export dialog asks); after the data-loss
  // checks, which say more about `-o walk.bvh`
  if (std::string problem = outputSuffixProblem(run.host, job.plugin, job.output); !problem.empty())
    return failure(kExitBadInput, job.output, problem);
  // the folder: a missing or read-only one is no bad input (exit 1: a farm retries it)
  std::error_code folderError;
  const std::filesystem::path absolute = std::filesystem::absolute(job.output, folderError);
  const std::string folder = absolute.parent_path().string();
  if (!std::filesystem::is_directory(folder, folderError))
    return failure(kExitFailure, job.output, "cannot write: the folder " + folder + " does not exist");
  if (::access(folder.c_str(), W_OK) != 0)
    return failure(kExitFailure, job.output, "cannot write: the folder " + folder + " is not writable");
  if (std::filesystem::is_directory(job.output, folderError))
    return failure(kExitFailure, job.output, "cannot write: it is a folder");
  if (!job.unitScale.empty()) {
    const std::optional<double> scale = parseUnitScale(job.unitScale);
    if (!scale)
      return failure(kExitBadInput, job.input,
                     "--unit-scale '" + job.unitScale +
                         "' is neither a positive number of cm per unit nor a preset (cm, m, mm, inch, cmu)");
    run.unitScale = *scale;
  }

  for (double ratio : job.meshRatios)
    if (!std::isfinite(ratio) || !(ratio > 0.0 && ratio <= 1.0))
      return failure(kExitBadInput, job.input, "--mesh-ratio " + std::to_string(ratio) + ": a triangle ratio must be in (0, 1]");
  if (!job.meshRatios.empty() && isProjectFile(job.input))
    return failure(kExitBadInput, job.input, "--mesh-ratio applies to a file; a project exports its own levels");
  if (job.skinning && isProjectFile(job.input))
    return failure(kExitBadInput, job.input,
                   "--skinning applies to a file's default LOD set; a project exports its own levels (their "
                   "skinning is the set's, chosen in the studio's Budget dialog)");
  if (job.skinning && !job.meshRatios.empty())
    return failure(kExitBadInput, job.input,
                   "--skinning applies to the default LOD set; --mesh-ratio levels keep the original motion");
  if (!job.character.empty() && !isProjectFile(job.input))
    return failure(kExitBadInput, job.input, "--character applies to a project; a file is its own character");
  if (!job.character.empty() && job.asset >= 0)
    return failure(kExitBadInput, job.input, "--character and --asset both pick what to export: give one");
  if (!job.motions.empty() && isProjectFile(job.input))
    return failure(kExitBadInput, job.input,
                   "--motion applies to a file; a project plays the motions its mappings assign to its character");
  return std::nullopt;
}

// 2-3. A project's character and the motions assigned to it imported, what the exporter
// cannot hold refused, the package built.
std::optional<ExportOutcome> buildFromProject(JobRun& run, Result<LodPackage>& package) {
  const ExportJob& job = run.job;
  Clock::time_point start = Clock::now();
  Result<Project> project = loadProjectFile(job.input, job.project);
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
    Result<Asset> asset = importFile(path, run.unitScale > 0.0 ? run.unitScale : entry.unitScale, job, run.cancel);
    if (!asset)
      return run.importFailure(path, asset.message());
    owned[std::size_t(a)] = std::make_unique<Asset>(std::move(asset).value());
    imported[std::size_t(a)] = owned[std::size_t(a)].get();
    return std::nullopt;
  };
  // --asset, else --character, else the character of the asset in view (exportCharacterOf(),
  // the studio's rule), else the first character (imported to be found)
  int character = job.asset;
  if (character < 0 && !job.character.empty()) {
    Result<int> named = exportCharacterNamed(*project, job.character);
    if (!named)
      return failure(kExitBadInput, job.input, "--character " + job.character + ": " + named.message());
    character = *named;
  }
  if (character < 0)
    character = exportCharacterOf(*project, project->view.asset);
  if (character < 0) {
    for (const ProjectMapping& mapping : project->mappings)
      if (std::optional<ExportOutcome> failed = importAt(mapping.character))
        return *failed;
    if (project->mappings.empty())
      for (int a = 0; a < assets; ++a)
        if (std::optional<ExportOutcome> failed = importAt(a))
          return *failed;
    character = exportCharacterOf(*project, project->view.asset, -1, imported);
  }
  run.out.character = assetFileName(*project, character);
  if (const std::vector<int> characters = exportCharacters(*project);
      job.asset < 0 && job.character.empty() && characters.size() > 1)
    run.notes.push_back("character " + run.out.character + " (asset " + std::to_string(character) +
                        ") of the project's " + std::to_string(characters.size()) + " (" +
                        exportCharacterList(*project) + "); --character NAME exports another");
  if (std::optional<ExportOutcome> failed = importAt(character))
    return *failed;
  for (const ProjectMapping& mapping : project->mappings)
    if (mapping.character == character)
      if (std::optional<ExportOutcome> failed = importAt(mapping.motion))
        return *failed;
  run.out.importSeconds = secondsSince(start);
  // what the format cannot hold, refused before the build (Exporter::planProblem())
  if (const QString problem = run.exporter->planProblem(packagePlan(*project, imported, character, job.levels));
      !problem.isEmpty())
    return failure(kExitBadInput, job.input, problem.toStdString());
  start = Clock::now();
  package = buildLodPackage(*project, imported, character, job.levels, run.packageProgress(), run.cancel);
  run.out.packageSeconds = secondsSince(start);
  return std::nullopt;
}

// 2. The clips of every --motion played on the file's character (mapMotionAutomatically(), the
// path bench-crowd --scene --motion takes), each mapping's reach noted; a mapping that drives
// too little of the character refused unless --allow-partial.
std::optional<ExportOutcome> mapMotions(JobRun& run, const Asset& character, std::vector<Clip>& out_clips) {
  const ExportJob& job = run.job;
  const std::string name = std::filesystem::path(job.input).stem().string();
  for (const std::string& file : job.motions) {
    Result<Asset> motion = importFile(file, 0.0, job, run.cancel);
    if (!motion)
      return run.importFailure(file, motion.message());
    Result<MappedMotion> mapped = mapMotionAutomatically(motion->skeleton, motion->clips, character.skeleton, name);
    if (!mapped)
      return failure(kExitBadInput, file, mapped.message());
    const MappingCoverage& coverage = mapped->coverage;
    const std::string reach = mappingReach(coverage, name);
    if (drivesTooLittle(coverage) && !job.allowPartial)
      return failure(kExitBadInput, file,
                     tooLittleMappedReason(coverage, name) + " (--allow-partial exports it anyway)");
    const std::string stem = std::filesystem::path(file).stem().string();
    for (Clip& clip : mapped->clips) {
      // named after its file (a BVH clip is "Motion"): animations <file>_LOD<n>, or
      // <file>_<clip>_LOD<n> for a file of several clips
      clip.name = mapped->clips.size() == 1 ? stem : stem + "_" + clip.name;
      run.notes.push_back("motion " + file + ": clip '" + clip.name + "' on " + name + ", " +
                          std::to_string(mapped->mapping.pairs.size()) + " joints mapped by name, driving " + reach +
                          "; the others hold their rest pose");
      out_clips.push_back(std::move(clip));
    }
  }
  return std::nullopt;
}

// 2-3. A file imported, what the exporter cannot hold refused, its default LOD set (or one
// level per --mesh-ratio) built.
std::optional<ExportOutcome> buildFromFile(JobRun& run, Result<LodPackage>& package) {
  const ExportJob& job = run.job;
  Clock::time_point start = Clock::now();
  Result<Asset> asset = importFile(job.input, run.unitScale, job, run.cancel);
  if (!asset)
    return run.importFailure(job.input, asset.message());
  std::vector<Clip> mapped; // --motion clips on the character
  if (std::optional<ExportOutcome> failed = mapMotions(run, *asset, mapped))
    return *failed;
  run.out.importSeconds = secondsSince(start);
  // a file gets the default set of 4 levels (docs/architecture.md section 6), or LOD0 and
  // one level per --mesh-ratio
  const int levelCount = job.meshRatios.empty() ? 4 : int(job.meshRatios.size()) + 1;
  LodPackagePlan plan = packagePlan(*asset, levelCount, job.levels);
  for (const Clip& clip : mapped)
    plan.clipFrames += static_cast<std::uint64_t>(clip.frameCount);
  if (const QString problem = run.exporter->planProblem(plan); !problem.isEmpty())
    return failure(kExitBadInput, job.input, problem.toStdString());
  start = Clock::now();
  try {
    if (job.meshRatios.empty()) {
      package = buildLodPackage(*asset, job.levels, run.packageProgress(), run.cancel, mapped,
                                job.skinning.value_or(LodSkinning::Gpu));
    } else {
      // LOD0 and one level per ratio, all with the original motion
      LodSet lods;
      lods.levels.resize(job.meshRatios.size() + 1);
      for (std::size_t i = 0; i < lods.levels.size(); ++i) {
        lods.levels[i].name = "LOD" + std::to_string(i);
        lods.levels[i].meshRatio = i == 0 ? 1.0 : job.meshRatios[i - 1];
      }
      JpcSettings jpc;
      jpc.zeroLength = 1e-6 * asset->unitScale; // docs/architecture.md section 4: 1e-6 file units
      package = buildLodPackage(*asset, lods, jpc, job.levels, run.packageProgress(), mapped, run.cancel);
    }
  } catch (const std::bad_alloc&) {
    return failure(kExitFailure, job.input, "not enough memory to build its LOD package");
  }
  run.out.packageSeconds = secondsSince(start);
  return std::nullopt;
}

// 4. The package written by the exporter (byte-exact where the name is not UTF-8).
ExportOutcome writePackage(JobRun& run, const LodPackage& package) {
  const ExportJob& job = run.job;
  const Clock::time_point start = Clock::now();
  std::optional<ByteExactOutput> exact;
  QString path = QString::fromStdString(job.output);
  if (QFile::encodeName(path).toStdString() != job.output) {
    exact.emplace();
    std::string reason;
    if (!exact->open(job.output, &path, &reason))
      return failure(kExitFailure, job.output, "cannot write: " + reason);
  }
  run.tell("export", 0.0, job.plugin);
  const ExportResult result = run.exporter->exportPackage(
      package, path, run.options,
      ExportProgress([&](double fraction, const QString& detail) { run.tell("export", fraction, detail.toStdString()); },
                     [&] { return run.cancelled(); }));
  QString text = result.message;
  const QStringList warnings = splitExportWarnings(&text);
  std::string message = text.toStdString();
  const std::string written = path.toStdString();
  for (std::size_t at = message.find(written); exact && at != std::string::npos; at = message.find(written, at))
    message.replace(at, written.size(), job.output); // the temporary name is no one's business
  std::string reason;
  if (exact && result.ok && !exact->commit(&reason))
    return failure(kExitFailure, job.output, "cannot write: " + reason);
  ExportOutcome out = run.out;
  out.exportSeconds = secondsSince(start);
  if (!result.ok) {
    if (message.rfind(job.output + ": ", 0) == 0) // the exporter named the output already
      message.erase(0, job.output.size() + 2);
    ExportOutcome failed = failure(kExitFailure, job.output, message);
    failed.importSeconds = out.importSeconds;
    failed.packageSeconds = out.packageSeconds;
    failed.exportSeconds = out.exportSeconds;
    return failed;
  }
  out.message.clear();
  for (const std::string& note : run.notes)
    out.message += note + "\n";
  out.message += message;
  for (const QString& warning : warnings)
    out.warnings.push_back(warning.toStdString());
  if (exact)
    out.message += " (the name is not valid UTF-8: the file has the exact name given; names inside it use U+FFFD)";
  std::error_code sizeError;
  out.bytes = static_cast<std::int64_t>(std::filesystem::file_size(job.output, sizeError));
  return out;
}

} // namespace

ExportOutcome runExportJob(const PluginHost& host, const ExportJob& job, const std::atomic<bool>* cancel,
                           const ExportJobProgress& report) {
  JobRun run{host, job, cancel, report, nullptr, {}, 0.0, {}, {}};
  if (std::optional<ExportOutcome> failed = checkJob(run))
    return *failed;
  run.tell("import", -1.0, job.input);
  Result<LodPackage> package = Error("no package");
  if (std::optional<ExportOutcome> failed =
          isProjectFile(job.input) ? buildFromProject(run, package) : buildFromFile(run, package))
    return *failed;
  if (!package) {
    if (package.message() == kLodPackageCancelled)
      return failure(kExitFailure, job.input, "cancelled: nothing was written");
    return failure(kExitBadInput, job.input, package.message());
  }
  run.out.levels = static_cast<int>(package->levels.size());
  if (run.cancelled())
    return failure(kExitFailure, job.input, "cancelled: nothing was written");
  return writePackage(run, *package);
}

} // namespace mlod::cli
