#include "example_exporter.h"

#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>

namespace mlod {

namespace {

QJsonObject clipMetrics(const JpcLevelResult& metrics) {
  return {{"simplified_joint_percent", metrics.simplifiedPercent},
          {"clusters", metrics.clusterCount},
          {"max_error", metrics.maxError},
          {"max_joint_position_error_cm", metrics.maxJointPositionErrorCm}};
}

QJsonObject levelSummary(const LodPackageLevel& level) {
  QJsonArray clips;
  for (const JpcLevelResult& metrics : level.metrics)
    clips.append(clipMetrics(metrics));
  const SkinnedMesh* mesh = level.mesh();
  return {{"index", level.index},
          {"name", QString::fromStdString(level.settings.name)},
          {"motion_threshold", level.settings.motionThreshold},
          {"mesh_ratio", level.settings.meshRatio},
          {"switch_distance_cm", level.settings.switchDistanceCm},
          {"active_joints", level.skeleton().jointCount()},
          {"triangles", mesh ? static_cast<qint64>(mesh->triangleCount()) : 0},
          {"clips", clips}};
}

} // namespace

QByteArray exampleSummaryJson(const LodPackage& package, bool indented, const ExportProgress& progress) {
  QJsonArray clips;
  for (const Clip& clip : package.clips)
    clips.append(QJsonObject{{"name", QString::fromStdString(clip.name)}, {"frames", clip.frameCount}, {"fps", clip.fps}});
  QJsonArray levels;
  for (std::size_t i = 0; i < package.levels.size(); ++i) {
    // Report before each level and stop as soon as the user cancels.
    if (!progress.step(double(i) / double(package.levels.size()),
                       QStringLiteral("level %1 of %2").arg(i + 1).arg(package.levels.size())))
      return {};
    levels.append(levelSummary(package.levels[i]));
  }
  const QJsonObject root{{"format", "motionlod-example-summary"},
                         {"format_version", 1},
                         {"name", QString::fromStdString(package.name)},
                         {"source", QString::fromStdString(package.sourcePath)},
                         {"unit_scale", package.unitScale},
                         {"joints", package.skeleton.jointCount()},
                         {"triangles", package.mesh ? static_cast<qint64>(package.mesh->triangleCount()) : 0},
                         {"clips", clips},
                         {"levels", levels}};
  return QJsonDocument(root).toJson(indented ? QJsonDocument::Indented : QJsonDocument::Compact);
}

ExporterOptions ExampleExporter::options() const {
  // Options are data: the studio builds a form from them, the CLI takes --option indent=false.
  ExporterOption indent;
  indent.key = QStringLiteral("indent");
  indent.type = ExporterOption::Bool;
  indent.defaultValue = true;
  indent.help = QStringLiteral("Indent the JSON for people (false: one compact line)");
  return {indent};
}

ExportResult ExampleExporter::exportPackage(const LodPackage& package, const QString& path, const QVariantMap& options,
                                            const ExportProgress& progress) {
  const QByteArray json = exampleSummaryJson(package, options.value(QStringLiteral("indent")).toBool(), progress);
  if (json.isEmpty())
    return cancelledResult();
  progress.report(1.0, QStringLiteral("writing"));
  // Written through a temporary file and renamed: a failure leaves nothing at `path`.
  return writeFileAtomically(path, json);
}

} // namespace mlod
