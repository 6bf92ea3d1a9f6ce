#include "report_exporter.h"

#include "report_document.h"

#include <QFileInfo>
#include <string>

namespace mlod {

ExporterOptions ReportExporter::options() const {
  ExporterOptions out;
  out.append({QStringLiteral("format"),
              ExporterOption::Choice,
              QStringLiteral("auto"),
              {},
              {},
              {QStringLiteral("auto"), QStringLiteral("html"), QStringLiteral("csv"), QStringLiteral("json")},
              QStringLiteral("html: a page with tables and charts; csv: one table; json: every figure; auto: from the "
                             "output's suffix")});
  out.append(
      {QStringLiteral("csv_table"),
       ExporterOption::Choice,
       QStringLiteral("levels"),
       {},
       {},
       {QStringLiteral("levels"), QStringLiteral("joints")},
       QStringLiteral("The table a CSV holds: one row per clip and level (Table 1), or per clip, level and joint")});
  out.append({QStringLiteral("indent"),
              ExporterOption::Int,
              2,
              0,
              8,
              {},
              QStringLiteral("Spaces of indentation in JSON (0: one line)")});
  return out;
}

ExportResult ReportExporter::exportPackage(const LodPackage& package, const QString& path, const QVariantMap& options,
                                           const ExportProgress& progress) {
  QString format = options.value(QStringLiteral("format"), QStringLiteral("auto")).toString();
  if (format == QLatin1String("auto")) {
    const QString suffix = QFileInfo(path).suffix().toLower();
    format = suffix == QLatin1String("csv") || suffix == QLatin1String("json") ? suffix : QStringLiteral("html");
  }
  if (!progress.step(0.0, QStringLiteral("gathering the figures")))
    return cancelledResult();
  const nlohmann::json document = report::reportJson(package);
  if (!progress.step(0.5, QStringLiteral("writing the %1 report").arg(format.toUpper())))
    return cancelledResult();
  std::string text;
  if (format == QLatin1String("json")) {
    const int indent = options.value(QStringLiteral("indent"), 2).toInt();
    text = document.dump(indent > 0 ? indent : -1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n"; // nlohmann: 0 still breaks lines, -1 does not
  } else if (format == QLatin1String("csv")) {
    const bool joints = options.value(QStringLiteral("csv_table")).toString() == QLatin1String("joints");
    text = report::reportCsv(document, joints ? report::CsvTable::Joints : report::CsvTable::Levels);
  } else if (format == QLatin1String("html")) {
    text = report::reportHtml(document);
  } else {
    return ExportResult::failure(
        QStringLiteral("option 'format': '%1' is not one of auto, html, csv, json").arg(format));
  }
  if (!progress.step(0.9, QStringLiteral("saving")))
    return cancelledResult();
  const ExportResult written = writeFileAtomically(path, QByteArray(text.data(), static_cast<qsizetype>(text.size())));
  if (!written.ok)
    return written;
  progress.report(1.0, QStringLiteral("done"));
  return ExportResult::success(QStringLiteral("wrote %1 (%2 report, %3 bytes): %4 levels, %5 clips")
                                   .arg(path, format.toUpper())
                                   .arg(text.size())
                                   .arg(package.levels.size())
                                   .arg(package.clips.size()));
}

} // namespace mlod
