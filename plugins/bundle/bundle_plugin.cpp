// The runtime bundle exporter (docs/architecture.md section 8): FILE.mlodb, the binary that
// src/runtime/bundle.h reads (docs/bundle-format.md), and FILE.mlodb.json beside it, a
// manifest for people and tools. Both land together or not at all.

#include "sdk/exporter.h"

#include <QFileInfo>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QObject>

#include <algorithm>

namespace {

using namespace mlod;

QJsonObject manifest(const LodPackage& package, const Bundle& bundle, const QString& file, std::size_t bytes,
                     std::uint32_t crc) {
  QJsonObject root;
  root["format"] = "motionlod-bundle";
  root["version"] = int(kBundleVersion);
  root["file"] = QFileInfo(file).fileName();
  root["bytes"] = qint64(bytes);
  root["crc32"] = QString("%1").arg(crc, 8, 16, QChar('0'));
  root["name"] = QString::fromStdString(bundle.name);
  root["source"] = QString::fromStdString(bundle.source);
  root["unit"] = "cm";
  root["bounding_radius_cm"] = bundle.boundingRadiusCm;
  root["projection"] = QJsonObject{{"vertical_fov_degrees", bundle.verticalFovDegrees},
                                    {"viewport_height_pixels", bundle.viewportHeightPixels}};
  root["joints"] = int(bundle.jointNames.size());
  QJsonArray levels;
  for (std::size_t l = 0; l < bundle.levels.size(); ++l) {
    const BundleLevel& level = bundle.levels[l];
    const LodPackageLevel& source = package.levels[l];
    QJsonObject entry{{"index", level.index},
                      {"name", QString::fromStdString(level.name)},
                      {"threshold", level.motionThreshold},
                      {"mesh_ratio", level.meshRatio},
                      {"switch_distance_cm", level.switchDistanceCm},
                      {"pixel_error", level.pixelError},
                      {"screen_size_pixels", level.screenSizePixels},
                      {"motion_error_cm", level.motionErrorCm},
                      {"mesh_error_cm", level.meshErrorCm},
                      {"joints", level.jointCount()}};
    QJsonArray clips;
    for (std::size_t c = 0; c < level.clips.size(); ++c) {
      const BundleClip& clip = level.clips[c];
      QJsonObject clipEntry{{"name", QString::fromStdString(clip.name)},
                            {"frames", clip.clip.frameCount()},
                            {"fps", clip.clip.fps()},
                            {"looping", clip.clip.looping()},
                            {"clusters", clip.clip.clusterCount()},
                            {"blend_frames", clip.clip.blendFrames()},
                            {"bytes", qint64(clip.clip.byteSize())},
                            {"bytes_per_second", clip.clip.bytesPerSecond()},
                            {"precision_cm", clip.clip.precisionCm()},
                            {"encoded_error_cm", clip.clip.encodedErrorCm()}};
      if (c < source.metrics.size()) {
        clipEntry["simplified_joint_percent"] = source.metrics[c].simplifiedPercent;
        clipEntry["max_joint_position_error_cm"] = source.metrics[c].maxJointPositionErrorCm;
      }
      clips.append(clipEntry);
    }
    entry["clips"] = clips;
    if (level.mesh)
      entry["mesh"] = QJsonObject{{"vertices", int(level.mesh->positions.size())},
                                  {"triangles", int(level.mesh->indices.size() / 3)},
                                  {"normals", !level.mesh->normals.empty()}};
    levels.append(entry);
  }
  root["levels"] = levels;
  return root;
}

} // namespace

class BundleExporter : public QObject, public mlod::Exporter {
  Q_OBJECT
  Q_PLUGIN_METADATA(IID "org.motionlod.Exporter/1" FILE "bundle_metadata.json")
  Q_INTERFACES(mlod::Exporter)

public:
  MLOD_EXPORTER_IDENTITY_FROM_METADATA
  mlod::ExporterOptions options() const override {
    mlod::ExporterOptions out;
    out.append({"manifest", mlod::ExporterOption::Bool, true, {}, {}, {},
                "Write FILE.mlodb.json beside the bundle: its levels, clips and sizes for people and tools"});
    out.append({"meshes", mlod::ExporterOption::Bool, true, {}, {}, {},
                "Store each level's skinning mesh (off: motion only, for a character whose mesh the engine has)"});
    out.append({"blend_frames", mlod::ExporterOption::Int, mlod::kDefaultBundleBlendFrames, 0, mlod::kMaxBlendFrames, {},
                "Frames over which a joint leaving a frozen cluster blends back, stored in the clips: the engine "
                "plays them with this many (0 = off)"});
    out.append({"precision_cm", mlod::ExporterOption::Double, mlod::kDefaultClipPrecisionCm, 0.0001, 10.0, {},
                "Quantization precision in cm: no joint, and no point 3 cm from one, moves further from the "
                "uncompressed clip"});
    return out;
  }

  QString planProblem(const mlod::LodPackagePlan& plan) const override {
    return QString::fromStdString(mlod::bundlePlanProblem(plan.clipFrames, plan.joints, plan.levels, plan.withOriginal));
  }
  mlod::ExportResult exportPackage(const mlod::LodPackage& package, const QString& path, const QVariantMap& options,
                                   const mlod::ExportProgress& progress) override {
    using namespace mlod;
    if (!progress.step(0.0, QStringLiteral("gathering %1 levels").arg(package.levels.size())))
      return cancelledResult();
    BundleOptions bundleOptions;
    bundleOptions.blendFrames = options.value("blend_frames", kDefaultBundleBlendFrames).toInt();
    bundleOptions.precisionCm = options.value("precision_cm", kDefaultClipPrecisionCm).toDouble();
    Result<Bundle> bundle = packageBundle(package, bundleOptions);
    if (!bundle)
      return ExportResult::failure(QString::fromStdString(bundle.message()));
    if (!options.value("meshes", true).toBool())
      for (BundleLevel& level : bundle->levels)
        level.mesh.reset();
    if (!progress.step(0.3, QStringLiteral("encoding")))
      return cancelledResult();
    std::string error;
    const std::vector<std::uint8_t> bytes = writeBundle(*bundle, &error);
    if (bytes.empty())
      return ExportResult::failure(QString::fromStdString(error));
    if (!progress.step(0.7, QStringLiteral("writing")))
      return cancelledResult();
    QList<QPair<QString, QByteArray>> files;
    files.append({path, QByteArray(reinterpret_cast<const char*>(bytes.data()), qsizetype(bytes.size()))});
    if (options.value("manifest", true).toBool()) {
      const QJsonObject json = manifest(package, *bundle, path, bytes.size(), crc32(bytes));
      files.append({path + QStringLiteral(".json"), QJsonDocument(json).toJson(QJsonDocument::Indented)});
    }
    ExportResult result = writeFilesAtomically(files);
    if (result.ok) {
      result.message = QStringLiteral("wrote %1 (%2 bytes, %3 levels)%4")
                           .arg(path)
                           .arg(bytes.size())
                           .arg(bundle->levels.size())
                           .arg(files.size() > 1 ? QStringLiteral(" and its manifest %1.json").arg(path) : QString());
      progress.report(1.0, QStringLiteral("done"));
    }
    return result;
  }
};

#include "bundle_plugin.moc"
