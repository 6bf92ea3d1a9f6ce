#pragma once
// The report exporter plugin (id "report"): the figures of a LodPackage as a self-contained
// HTML page (tables and inline SVG charts), CSV or JSON (report_document.h, README.md).

#include "sdk/exporter.h"

#include <QObject>

namespace mlod {

class ReportExporter : public QObject, public Exporter {
  Q_OBJECT
  Q_PLUGIN_METADATA(IID "org.motionlod.Exporter/1" FILE "report_metadata.json")
  Q_INTERFACES(mlod::Exporter)

public:
  MLOD_EXPORTER_IDENTITY_FROM_METADATA
  // format (auto|html|csv|json: auto follows the output's suffix, HTML when it has none of
  // them), csv_table (levels|joints: which table a CSV holds), indent (JSON indentation).
  ExporterOptions options() const override;
  ExportResult exportPackage(const LodPackage& package, const QString& path, const QVariantMap& options,
                             const ExportProgress& progress) override;
};

} // namespace mlod
