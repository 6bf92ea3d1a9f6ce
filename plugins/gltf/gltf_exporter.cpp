#include "gltf_exporter.h"

#include "gltf_writer.h"

#include <QFileInfo>

namespace mlod {

ExporterOptions GltfExporter::options() const {
  ExporterOptions out;
  out.append({QStringLiteral("format"),
              ExporterOption::Choice,
              QStringLiteral("auto"),
              {},
              {},
              {QStringLiteral("auto"), QStringLiteral("glb"), QStringLiteral("gltf")},
              QStringLiteral("glb: binary glTF; gltf: JSON with the buffer embedded; auto: from the output's suffix")});
  out.append({QStringLiteral("pretty"),
              ExporterOption::Bool,
              false,
              {},
              {},
              {},
              QStringLiteral("Indent the JSON of a .gltf for people to read (larger file)")});
  return out;
}

ExportResult GltfExporter::exportPackage(const LodPackage& package, const QString& path, const QVariantMap& options,
                                         const ExportProgress& progress) {
  QString format = options.value(QStringLiteral("format"), QStringLiteral("auto")).toString();
  if (format == QLatin1String("auto"))
    format = QFileInfo(path).suffix().compare(QLatin1String("gltf"), Qt::CaseInsensitive) == 0 ? QStringLiteral("gltf")
                                                                                               : QStringLiteral("glb");
  if (format != QLatin1String("glb") && format != QLatin1String("gltf"))
    return ExportResult::failure(QStringLiteral("option 'format': '%1' is not one of auto, glb, gltf").arg(format));

  gltf::WriteOptions write;
  write.binary = format == QLatin1String("glb");
  write.pretty = options.value(QStringLiteral("pretty"), false).toBool();
  write.generator = "Motion LOD Studio glTF exporter " MLOD_PLUGIN_VERSION;
  const Result<std::string> bytes = gltf::writeGltf(package, write, [&](double fraction, std::string_view message) {
    return progress.step(0.95 * fraction, QString::fromUtf8(message.data(), qsizetype(message.size())));
  });
  if (!bytes) {
    if (bytes.message() == gltf::kWriteCancelled)
      return cancelledResult();
    return ExportResult::failure(QString::fromStdString(bytes.message()));
  }
  if (progress.cancelled())
    return cancelledResult();
  const ExportResult written =
      writeFileAtomically(path, QByteArray(bytes->data(), static_cast<qsizetype>(bytes->size())));
  if (!written.ok)
    return written;
  progress.report(1.0, QStringLiteral("done"));
  int meshes = 0;
  for (const LodPackageLevel& level : package.levels)
    meshes += level.mesh() ? 1 : 0;
  return ExportResult::success(QStringLiteral("wrote %1 (%2, %3 bytes): %4 levels, %5 meshes, %6 animations")
                                   .arg(path, format.toUpper())
                                   .arg(bytes->size())
                                   .arg(package.levels.size())
                                   .arg(meshes)
                                   .arg(package.levels.size() * (package.skeleton.empty() ? 0 : package.clips.size())));
}

} // namespace mlod
