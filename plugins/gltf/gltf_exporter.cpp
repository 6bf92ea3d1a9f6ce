#include "gltf_exporter.h"

#include "gltf_writer.h"

#include <QFileInfo>
#include <algorithm>

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
  out.append({QStringLiteral("split_levels"),
              ExporterOption::Bool,
              false,
              {},
              {},
              {},
              QStringLiteral("One file per level, OUT_LOD0.glb, OUT_LOD1.glb ...: each a complete character with "
                             "its level's mesh and animations (for pipelines that take one file per level)")});
  out.append({QStringLiteral("compress"),
              ExporterOption::Choice,
              QStringLiteral("none"),
              {},
              {},
              {QStringLiteral("none"), QStringLiteral("meshopt")},
              QStringLiteral("meshopt: every buffer compressed with meshoptimizer (EXT_meshopt_compression and "
                             "KHR_mesh_quantization, required): for three.js, Babylon.js and engines with a meshopt "
                             "decoder; Blender 3.4 and Assimp cannot read it")});
  out.append({QStringLiteral("rotations"),
              ExporterOption::Choice,
              QStringLiteral("short"),
              {},
              {},
              {QStringLiteral("short"), QStringLiteral("float")},
              QStringLiteral("short: rotation keys as normalized 16-bit integers (glTF core, at most 0.0035 degrees "
                             "off); float: 32-bit floats, for readers that misread the former (Assimp 5.2); not with "
                             "compress=meshopt")});
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
  const bool split = options.value(QStringLiteral("split_levels"), false).toBool();
  const QString compress = options.value(QStringLiteral("compress"), QStringLiteral("none")).toString();
  if (compress != QLatin1String("none") && compress != QLatin1String("meshopt"))
    return ExportResult::failure(QStringLiteral("option 'compress': '%1' is not one of none, meshopt").arg(compress));
  write.compression = compress == QLatin1String("meshopt") ? gltf::Compression::Meshopt : gltf::Compression::None;
  const QString rotations = options.value(QStringLiteral("rotations"), QStringLiteral("short")).toString();
  if (rotations != QLatin1String("short") && rotations != QLatin1String("float"))
    return ExportResult::failure(QStringLiteral("option 'rotations': '%1' is not one of short, float").arg(rotations));
  write.floatRotations = rotations == QLatin1String("float");
  if (write.floatRotations && write.compression == gltf::Compression::Meshopt)
    return ExportResult::failure(
        QStringLiteral("option 'rotations': float keys are not compressed (compress=meshopt stores 16-bit keys)"));

  // The files to write: OUT, or with split_levels OUT_LOD<n>.<suffix> per level.
  QList<QPair<QString, std::vector<std::size_t>>> outputs;
  if (split) {
    const QFileInfo info(path);
    const QString suffix = info.suffix().isEmpty() ? format : info.suffix();
    const QString stem = info.suffix().isEmpty() ? info.filePath() : info.filePath().chopped(suffix.size() + 1);
    for (std::size_t i = 0; i < package.levels.size(); ++i)
      outputs.append({QStringLiteral("%1_LOD%2.%3").arg(stem).arg(i).arg(suffix), {i}});
  } else {
    outputs.append({path, {}});
  }
  QList<QPair<QString, QByteArray>> files;
  std::vector<gltf::LevelStats> levels;
  QStringList warnings;
  double rotationDegrees = 0.0, rotationCm = 0.0;
  for (qsizetype k = 0; k < outputs.size(); ++k) {
    write.levels = outputs[k].second;
    const double from = double(k) / double(outputs.size());
    const double span = 1.0 / double(outputs.size());
    gltf::WriteStats stats;
    const Result<std::string> bytes = gltf::writeGltf(
        package, write,
        [&](double fraction, std::string_view message) {
          return progress.step(0.95 * (from + span * fraction),
                               QString::fromUtf8(message.data(), qsizetype(message.size())));
        },
        &stats);
    if (!bytes) {
      if (bytes.message() == gltf::kWriteCancelled)
        return cancelledResult();
      return ExportResult::failure(QString::fromStdString(bytes.message()));
    }
    files.append({outputs[k].first, QByteArray(bytes->data(), static_cast<qsizetype>(bytes->size()))});
    levels.insert(levels.end(), stats.levels.begin(), stats.levels.end());
    rotationDegrees = std::max(rotationDegrees, stats.rotationErrorDegrees);
    rotationCm = std::max(rotationCm, stats.rotationErrorCm);
    for (const std::string& warning : stats.warnings)
      if (!warnings.contains(QString::fromStdString(warning)))
        warnings << QString::fromStdString(warning);
  }
  if (progress.cancelled())
    return cancelledResult();
  const ExportResult written = writeFilesAtomically(files);
  if (!written.ok)
    return written;
  progress.report(1.0, QStringLiteral("done"));
  int meshes = 0;
  for (const LodPackageLevel& level : package.levels)
    meshes += level.mesh() ? 1 : 0;
  QStringList names;
  qint64 total = 0;
  for (const auto& [file, data] : files) {
    names << file;
    total += data.size();
  }
  QString message = QStringLiteral("wrote %1 (%2, %3 bytes): %4 levels, %5 meshes, %6 animations")
                        .arg(names.join(QStringLiteral(", ")), format.toUpper())
                        .arg(total)
                        .arg(package.levels.size())
                        .arg(meshes)
                        .arg(package.levels.size() * (package.skeleton.empty() ? 0 : package.clips.size()));
  if (!package.skeleton.empty()) {
    QStringList perLevel;
    for (const gltf::LevelStats& level : levels)
      perLevel << QStringLiteral("%1 %2 bytes (%3 rotation keys)")
                      .arg(QString::fromStdString(level.name))
                      .arg(level.animationBytes)
                      .arg(level.rotationKeys);
    message += QStringLiteral("\nanimation bytes per level: ") + perLevel.join(QStringLiteral(", "));
    // what the 16-bit rotation keys add to each level's motion error (WriteStats)
    if (write.floatRotations)
      message += QStringLiteral("\nrotation keys as 32-bit floats");
    else
      message += QStringLiteral("\nrotation keys as 16-bit integers: at most %1 degrees from the level's motion, "
                                "%2 cm at the joints")
                     .arg(rotationDegrees, 0, 'f', 5)
                     .arg(rotationCm, 0, 'f', 4);
  }
  for (const QString& warning : warnings)
    message += QLatin1Char('\n') + QString::fromLatin1(kExportWarningPrefix) + warning;
  return ExportResult::success(message);
}

} // namespace mlod
