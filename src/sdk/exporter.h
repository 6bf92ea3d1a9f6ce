#pragma once
// The exporter plugin interface (docs/architecture.md section 8). An exporter turns a LodPackage
// (core/lod/lod_package.h: everything computed; exporters never recompute) into files. It
// describes its options as data, so the editor builds a form and the CLI takes
// `--option key=value`; it reports progress and honours cancel through ExportProgress; it
// never shows a widget.
//
// A plugin is a QObject that implements mlod::Exporter, declared with
//     Q_OBJECT
//     Q_PLUGIN_METADATA(IID "org.motionlod.Exporter/1" FILE "metadata.json")
//     Q_INTERFACES(mlod::Exporter)
// and built with add_exporter_plugin() (cmake/MlodPlugins.cmake), which writes the metadata
// (id, name, version, suffixes, interface version) that the host reads before loading.
//
// Output files: write them with writeFileAtomically() / writeFilesAtomically() (or
// QSaveFile) so that a failed or cancelled export leaves nothing behind.

#include "core/lod/lod_package.h"

#include <QByteArray>
#include <QList>
#include <QPair>
#include <QString>
#include <QStringList>
#include <QVariant>
#include <QVariantMap>
#include <QtPlugin>

#include <functional>

namespace mlod {

// The interface id and its version: a plugin built against another version is refused.
inline constexpr const char* kExporterIid = "org.motionlod.Exporter/1";
inline constexpr int kExporterInterfaceVersion = 1;

// One option of an exporter, described as data.
struct ExporterOption {
  enum Type { Bool, Int, Double, String, Choice };
  QString key;           // "binary", "scale" ...: [a-z0-9_-]+
  Type type = String;
  QVariant defaultValue; // of the option's type (a Choice: one of `choices`)
  QVariant minimum;      // Int / Double: the range, inclusive; invalid = unbounded
  QVariant maximum;
  QStringList choices;   // Choice: the allowed values
  QString help;          // one sentence, shown as a tooltip and by the CLI
};
using ExporterOptions = QList<ExporterOption>;

const char* toString(ExporterOption::Type type); // "bool", "int", "double", "string", "choice"

struct ExportResult {
  bool ok = false;
  // What was written (ok) or why nothing was (not ok). A line that begins with
  // kExportWarningPrefix is a warning: what the written file lacks that a reader may look
  // for. The CLI prints warnings on stderr (splitExportWarnings()), the studio with the rest.
  QString message;
  static ExportResult success(const QString& message) { return {true, message}; }
  static ExportResult failure(const QString& message) { return {false, message}; }
};

inline constexpr const char* kExportWarningPrefix = "warning: ";

// The warnings of `inout_message` (its lines that begin with kExportWarningPrefix, without
// the prefix), in order; the other lines stay in `inout_message`.
QStringList splitExportWarnings(QString* inout_message);

// Progress of one export: report(fraction in [0, 1], message), and whether the user asked
// to cancel. Both may be called from the exporting thread; either callback may be empty.
class ExportProgress {
public:
  using Report = std::function<void(double fraction, const QString& message)>;
  using Cancelled = std::function<bool()>;
  ExportProgress() = default;
  ExportProgress(Report report, Cancelled cancelled) : m_report(std::move(report)), m_cancelled(std::move(cancelled)) {}

  void report(double fraction, const QString& message) const;
  bool cancelled() const { return m_cancelled && m_cancelled(); }
  // report() and then cancelled(): `if (!progress.step(0.5, "meshes")) return cancelledResult();`
  bool step(double fraction, const QString& message) const {
    report(fraction, message);
    return !cancelled();
  }

private:
  Report m_report;
  Cancelled m_cancelled;
};

// The result of a cancelled export ("cancelled: nothing was written").
ExportResult cancelledResult();

class Exporter {
public:
  virtual ~Exporter() = default;
  virtual QString id() const = 0;          // "gltf", "bundle", "report": what --plugin takes
  virtual QString name() const = 0;        // for people: "glTF 2.0 with LODs"
  virtual QString version() const = 0;     // the plugin's own version, "1.0.0"
  virtual QStringList suffixes() const = 0; // without the dot, the default first: {"glb", "gltf"}
  virtual ExporterOptions options() const = 0;
  // Writes `package` to `path`. `options` holds every option of options(), of its type
  // (checkExporterOptions() gives them so). Called off the UI thread; never shows a widget.
  // `motionlod batch --jobs K` calls it from several threads at once: keep no state between
  // calls.
  // On failure or cancel, leaves nothing at `path` (nor beside it) and says why.
  virtual ExportResult exportPackage(const LodPackage& package, const QString& path, const QVariantMap& options,
                                     const ExportProgress& progress) = 0;
  // Why a package of `plan` cannot be written by this exporter, or empty: asked before the
  // package is built (the command line and the studio alike), so that what the format
  // cannot hold is refused at once rather than after minutes of work. Refuses nothing
  // unless overridden (declared last: earlier slots keep their places).
  virtual QString planProblem(const LodPackagePlan& plan) const;
};

// Every option at its default.
QVariantMap defaultExporterOptions(const ExporterOptions& options);

// `values` checked against `options` and completed with defaults: unknown keys, values
// that do not convert to the option's type (strings are parsed: "true"/"false"/"1"/"0"/
// "yes"/"no" for Bool), values out of range or not among the choices are errors (false,
// with *out_error saying which option and why). On success *out_values holds every option,
// converted to its type.
bool checkExporterOptions(const ExporterOptions& options, const QVariantMap& values, QVariantMap* out_values,
                          QString* out_error);

// `key=value` strings (the CLI's --option) parsed and checked as above.
bool parseExporterOptions(const ExporterOptions& options, const QStringList& keyValues, QVariantMap* out_values,
                          QString* out_error);

// Writes `data` to `path` through a temporary file in the same folder, fsync'ed, renamed at
// the end: on any failure nothing is left at `path` (an existing file is kept as it was).
// The message of a failure names the file and the system's reason ("No space left on
// device"). Temporaries a killed writer left beside `path` are removed (atomic_write.cpp).
ExportResult writeFileAtomically(const QString& path, const QByteArray& data);

// Several files that belong together (a bundle and its manifest): every file is written to
// a temporary file and fsync'ed first; only when all are written are they renamed into
// place, in order, under an exclusive lock on their folders (two writers of one set land
// one whole set after the other). Each takes its place by exchanging names with the file it
// replaces (renameat2 RENAME_EXCHANGE; where the file system cannot, that file is renamed
// aside first, and copied only where neither works), so the previous version is kept
// without a hard link, whoever owns it. If a file cannot take its place, the files already
// placed get their previous version back, or go where there was none: the previous set
// stays intact. A kill between two renames can leave
// the first file new and the second old: give the second a checksum of the first (the
// bundle's manifest carries its CRC-32).
ExportResult writeFilesAtomically(const QList<QPair<QString, QByteArray>>& files);

// Whether `path` ends in one of `suffixes` (without the dot; any case). A file's suffix says
// its format, so the Export dialog and `motionlod export` / `batch` refuse an output whose
// suffix is not one of the plugin's (a GLB named x.mlodb would mislead every tool that opens it).
bool hasSuffix(const QString& path, const QStringList& suffixes);

// The suffixes as a message names them: ".glb or .gltf", ".html, .csv or .json".
QString suffixesText(const QStringList& suffixes);

// `path` with `suffix` (without the dot) appended unless it already ends with one of `suffixes`.
QString withSuffix(const QString& path, const QString& suffix, const QStringList& suffixes);

} // namespace mlod

#define MLOD_EXPORTER_IID "org.motionlod.Exporter/1"

// id(), name(), version() and suffixes() as add_exporter_plugin() wrote them into the
// plugin's metadata (the MLOD_PLUGIN_* compile definitions of its target), so the code says
// what the host read before loading (it refuses a plugin whose id() differs). Put it in
// the public section of the exporter class.
#define MLOD_EXPORTER_IDENTITY_FROM_METADATA                                                                        \
  QString id() const override { return QStringLiteral(MLOD_PLUGIN_ID); }                                           \
  QString name() const override { return QStringLiteral(MLOD_PLUGIN_NAME); }                                       \
  QString version() const override { return QStringLiteral(MLOD_PLUGIN_VERSION); }                                 \
  QStringList suffixes() const override { return QString(MLOD_PLUGIN_SUFFIXES).split(','); }
Q_DECLARE_INTERFACE(mlod::Exporter, MLOD_EXPORTER_IID)
