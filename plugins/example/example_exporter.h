#pragma once
// The example exporter (docs/plugin-guide.md walks through it): writes a small JSON summary
// of a LodPackage — per level its settings, what the LOD set generator measured, and the
// paper's Table 1 per clip. Copy this folder to start a new exporter.
//
// Output (one JSON document, lengths in cm, thresholds and errors E in cm·degrees):
//   {"format": "motionlod-example-summary", "format_version": 1,
//    "name", "source", "unit_scale", "joints", "triangles",
//    "clips": [{"name", "frames", "fps"}],
//    "levels": [{"index", "name", "motion_threshold", "mesh_ratio", "switch_distance_cm",
//                "active_joints", "triangles",
//                "clips": [{"simplified_joint_percent", "clusters", "max_error",
//                           "max_joint_position_error_cm"}]}]}
// "triangles" is 0 for a package without a mesh.

#include "sdk/exporter.h"

#include <QByteArray>
#include <QObject>

namespace mlod {

// The summary of `package` as a JSON document (indented or compact). Returns an empty
// array when the progress asks to cancel.
QByteArray exampleSummaryJson(const LodPackage& package, bool indented, const ExportProgress& progress);

class ExampleExporter : public QObject, public Exporter {
  Q_OBJECT
  Q_PLUGIN_METADATA(IID "org.motionlod.Exporter/1" FILE "example_metadata.json")
  Q_INTERFACES(mlod::Exporter)

public:
  // id, name, version and suffixes come from add_exporter_plugin() in CMakeLists.txt, so
  // they always say what the metadata the host reads says.
  MLOD_EXPORTER_IDENTITY_FROM_METADATA
  ExporterOptions options() const override;
  ExportResult exportPackage(const LodPackage& package, const QString& path, const QVariantMap& options,
                             const ExportProgress& progress) override;
};

} // namespace mlod
