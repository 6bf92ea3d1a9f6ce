#pragma once
// The glTF 2.0 exporter plugin (id "gltf"): a LodPackage as one .glb or .gltf with every
// level's mesh linked by MSFT_lod, one animation per level and clip, and the cluster tables
// in the MLOD_joint_clusters vendor extension (gltf_writer.h, docs/gltf-extension.md).

#include "sdk/exporter.h"

#include <QObject>

namespace mlod {

class GltfExporter : public QObject, public Exporter {
  Q_OBJECT
  Q_PLUGIN_METADATA(IID "org.motionlod.Exporter/1" FILE "gltf_metadata.json")
  Q_INTERFACES(mlod::Exporter)

public:
  MLOD_EXPORTER_IDENTITY_FROM_METADATA
  // format (auto|glb|gltf: auto follows the output's suffix, .glb when it has neither),
  // pretty (indent the JSON of a .gltf), split_levels (OUT_LOD0.glb, OUT_LOD1.glb ... instead
  // of OUT: one complete character per level, written together or not at all). The message
  // of a success ends with the animation bytes of every level.
  ExporterOptions options() const override;
  ExportResult exportPackage(const LodPackage& package, const QString& path, const QVariantMap& options,
                             const ExportProgress& progress) override;
};

} // namespace mlod
