#include "exporter_test_support.h"

#include "io/importer.h"
#include "test_files.h"

#include <QDir>
#include <QPluginLoader>
#include <QProcess>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <optional>

namespace mlod::test {

namespace {} // namespace

std::optional<LodPackage> packageOf(const std::string& file, double unitScale) {
  ImportOptions options;
  options.unitScale = unitScale;
  Result<Asset> asset = importAsset(modelPath(file), options);
  if (!asset) {
    ADD_FAILURE() << file << ": " << asset.message();
    return std::nullopt;
  }
  Result<LodPackage> package = buildLodPackage(*asset);
  if (!package) {
    ADD_FAILURE() << file << ": " << package.message();
    return std::nullopt;
  }
  return std::move(package).value();
}

namespace {

const LodPackage& orEmpty(const std::optional<LodPackage>& package) {
  static const LodPackage empty;
  return package ? *package : empty;
}

} // namespace

const LodPackage& cmuPackage() {
  static const std::optional<LodPackage> package = packageOf("BVH/01_01.bvh", 2.54 / 0.45);
  return orEmpty(package);
}

const LodPackage& bcnPackage() {
  static const std::optional<LodPackage> package = packageOf("X/BCN_Epileptic.X", 100.0);
  return orEmpty(package);
}

Exporter* loadExporter(const QString& path) {
  auto* loader = new QPluginLoader(path); // kept: the plugin stays loaded for the program's life
  QObject* instance = loader->instance();
  if (!instance) {
    ADD_FAILURE() << "cannot load " << path.toStdString() << ": " << loader->errorString().toStdString();
    return nullptr;
  }
  auto* exporter = qobject_cast<Exporter*>(instance);
  if (!exporter)
    ADD_FAILURE() << path.toStdString() << " is not an exporter";
  return exporter;
}

QVariantMap exporterOptions(const Exporter& exporter, const QStringList& values) {
  QVariantMap out;
  QString error;
  if (!parseExporterOptions(exporter.options(), values, &out, &error))
    ADD_FAILURE() << values.join(' ').toStdString() << ": " << error.toStdString();
  return out;
}

ValidatorReport runValidator(const QString& file) {
  ValidatorReport report;
  QProcess node;
  node.start(QStringLiteral(MLOD_NODE), {QStringLiteral(MLOD_VALIDATOR_JS), file});
  if (!node.waitForFinished(300000)) {
    report.output = "node did not finish: " + node.errorString().toStdString();
    return report;
  }
  report.exitCode = node.exitStatus() == QProcess::NormalExit ? node.exitCode() : -1;
  report.output = node.readAllStandardOutput().toStdString();
  const std::string errors = node.readAllStandardError().toStdString();
  try {
    const nlohmann::json json = nlohmann::json::parse(report.output);
    report.errors = json.at("numErrors").get<int>();
    report.warnings = json.at("numWarnings").get<int>();
    report.infos = json.at("numInfos").get<int>();
  } catch (const std::exception&) {
    report.output += errors;
  }
  return report;
}

bool haveNode() {
  const std::string node = MLOD_NODE;
  return !node.empty() && node.find("NOTFOUND") == std::string::npos;
}

LoaderReport runLoaders(const QString& file, int animation, double seconds) {
  LoaderReport report;
  QProcess node;
  node.start(QStringLiteral(MLOD_NODE),
             {QStringLiteral(MLOD_LOADERS_JS), file, QString::number(animation), QString::number(seconds, 'g', 17)});
  if (!node.waitForFinished(300000)) {
    report.errors = "node did not finish: " + node.errorString().toStdString();
    return report;
  }
  report.exitCode = node.exitStatus() == QProcess::NormalExit ? node.exitCode() : -1;
  report.output = node.readAllStandardOutput().toStdString();
  report.errors = node.readAllStandardError().toStdString();
  return report;
}

QStringList filesIn(const QString& dir) {
  return QDir(dir).entryList(QDir::Files | QDir::Hidden | QDir::System | QDir::NoDotAndDotDot);
}

} // namespace mlod::test
