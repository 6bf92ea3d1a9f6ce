#pragma once
// What the test plugins share: an exporter that writes a short text summary of the package
// (one line per level), honours cancel between levels, and fails on request. The plugins
// differ in how they are built (good, broken, wrong IID, old interface version, static).

#include "sdk/exporter.h"

#include <QObject>

namespace mlod::test {

class SummaryExporter : public Exporter {
public:
  MLOD_EXPORTER_IDENTITY_FROM_METADATA
  ExporterOptions options() const override {
    ExporterOptions out;
    out.append({"fail", ExporterOption::Bool, false, {}, {}, {}, "Fail instead of writing"});
    out.append({"title", ExporterOption::String, QString("summary"), {}, {}, {}, "First line"});
    return out;
  }
  ExportResult exportPackage(const LodPackage& package, const QString& path, const QVariantMap& options,
                             const ExportProgress& progress) override {
    QByteArray text = options.value("title").toString().toUtf8() + '\n';
    text += QByteArray::fromStdString(package.name) + '\n';
    for (std::size_t i = 0; i < package.levels.size(); ++i) {
      if (!progress.step(double(i) / double(package.levels.size()), QStringLiteral("level %1").arg(i)))
        return cancelledResult();
      const LodPackageLevel& level = package.levels[i];
      text += QStringLiteral("%1 %2 %3 %4\n")
                  .arg(level.index)
                  .arg(QString::fromStdString(level.settings.name))
                  .arg(level.skeleton().jointCount())
                  .arg(level.runtimeClips.size())
                  .toUtf8();
    }
    if (options.value("fail").toBool())
      return ExportResult::failure(QStringLiteral("failed on request"));
    progress.report(1.0, QStringLiteral("writing"));
    return writeFileAtomically(path, text);
  }
};

} // namespace mlod::test
