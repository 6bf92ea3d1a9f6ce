#include "sdk/exporter.h"

#include <QDir>
#include <algorithm>
#include <QFileInfo>

#include <cmath>
#include <filesystem>
#include <memory>
#include <system_error>
#include <vector>

namespace mlod {

const char* toString(ExporterOption::Type type) {
  switch (type) {
  case ExporterOption::Bool: return "bool";
  case ExporterOption::Int: return "int";
  case ExporterOption::Double: return "double";
  case ExporterOption::String: return "string";
  case ExporterOption::Choice: return "choice";
  }
  return "string";
}

void ExportProgress::report(double fraction, const QString& message) const {
  if (m_report)
    m_report(std::isfinite(fraction) ? std::clamp(fraction, 0.0, 1.0) : 0.0, message);
}

QString Exporter::planProblem(const LodPackagePlan&) const {
  return {};
}

ExportResult cancelledResult() {
  return ExportResult::failure(QStringLiteral("cancelled: nothing was written"));
}

QStringList splitExportWarnings(QString* inout_message) {
  QStringList warnings, rest;
  const QString prefix = QString::fromLatin1(kExportWarningPrefix);
  for (const QString& line : inout_message->split(QLatin1Char('\n'))) {
    if (line.startsWith(prefix))
      warnings << line.mid(prefix.size());
    else
      rest << line;
  }
  *inout_message = rest.join(QLatin1Char('\n'));
  return warnings;
}

QVariantMap defaultExporterOptions(const ExporterOptions& options) {
  QVariantMap out;
  for (const ExporterOption& option : options)
    out.insert(option.key, option.defaultValue);
  return out;
}

namespace {

bool fail(QString* out_error, const QString& message) {
  if (out_error)
    *out_error = message;
  return false;
}

// `value` as the option's type, or an invalid QVariant.
QVariant convert(const ExporterOption& option, const QVariant& value, QString* out_reason) {
  const bool isText = value.typeId() == QMetaType::QString;
  const QString text = value.toString().trimmed();
  switch (option.type) {
  case ExporterOption::Bool: {
    if (value.typeId() == QMetaType::Bool)
      return value;
    const QString lower = text.toLower();
    if (lower == "true" || lower == "1" || lower == "yes" || lower == "on")
      return true;
    if (lower == "false" || lower == "0" || lower == "no" || lower == "off")
      return false;
    *out_reason = QStringLiteral("'%1' is not a bool (true or false)").arg(text);
    return {};
  }
  case ExporterOption::Int: {
    bool ok = false;
    const qlonglong n = isText ? text.toLongLong(&ok) : value.toLongLong(&ok);
    if (!ok || (!isText && value.typeId() == QMetaType::Double && value.toDouble() != double(n))) {
      *out_reason = QStringLiteral("'%1' is not an integer").arg(text);
      return {};
    }
    if ((option.minimum.isValid() && n < option.minimum.toLongLong()) ||
        (option.maximum.isValid() && n > option.maximum.toLongLong())) {
      *out_reason = QStringLiteral("%1 is out of range [%2, %3]")
                        .arg(n)
                        .arg(option.minimum.isValid() ? option.minimum.toString() : QStringLiteral("-inf"),
                             option.maximum.isValid() ? option.maximum.toString() : QStringLiteral("inf"));
      return {};
    }
    return QVariant::fromValue(static_cast<int>(n));
  }
  case ExporterOption::Double: {
    bool ok = false;
    const double x = isText ? text.toDouble(&ok) : value.toDouble(&ok);
    if (!ok || !std::isfinite(x)) {
      *out_reason = QStringLiteral("'%1' is not a finite number").arg(text);
      return {};
    }
    if ((option.minimum.isValid() && x < option.minimum.toDouble()) ||
        (option.maximum.isValid() && x > option.maximum.toDouble())) {
      *out_reason = QStringLiteral("%1 is out of range [%2, %3]")
                        .arg(x)
                        .arg(option.minimum.isValid() ? option.minimum.toString() : QStringLiteral("-inf"),
                             option.maximum.isValid() ? option.maximum.toString() : QStringLiteral("inf"));
      return {};
    }
    return x;
  }
  case ExporterOption::String:
    if (!value.canConvert<QString>()) {
      *out_reason = QStringLiteral("not text");
      return {};
    }
    return value.toString();
  case ExporterOption::Choice:
    if (!option.choices.contains(value.toString())) {
      *out_reason = QStringLiteral("'%1' is not one of %2").arg(value.toString(), option.choices.join(", "));
      return {};
    }
    return value.toString();
  }
  return {};
}

} // namespace

bool checkExporterOptions(const ExporterOptions& options, const QVariantMap& values, QVariantMap* out_values,
                          QString* out_error) {
  QVariantMap out = defaultExporterOptions(options);
  for (auto it = values.begin(); it != values.end(); ++it) {
    const ExporterOption* option = nullptr;
    for (const ExporterOption& candidate : options)
      if (candidate.key == it.key())
        option = &candidate;
    if (!option) {
      QStringList keys;
      for (const ExporterOption& candidate : options)
        keys << candidate.key;
      return fail(out_error, QStringLiteral("unknown option '%1' (options: %2)")
                                 .arg(it.key(), keys.isEmpty() ? QStringLiteral("none") : keys.join(", ")));
    }
    QString reason;
    const QVariant converted = convert(*option, it.value(), &reason);
    if (!converted.isValid())
      return fail(out_error, QStringLiteral("option '%1': %2").arg(it.key(), reason));
    out.insert(it.key(), converted);
  }
  if (out_values)
    *out_values = out;
  return true;
}

bool parseExporterOptions(const ExporterOptions& options, const QStringList& keyValues, QVariantMap* out_values,
                          QString* out_error) {
  QVariantMap values;
  for (const QString& entry : keyValues) {
    const qsizetype equals = entry.indexOf('=');
    if (equals <= 0)
      return fail(out_error, QStringLiteral("option '%1' is not key=value").arg(entry));
    const QString key = entry.left(equals).trimmed();
    if (values.contains(key))
      return fail(out_error, QStringLiteral("option '%1' is given twice").arg(key));
    values.insert(key, entry.mid(equals + 1));
  }
  return checkExporterOptions(options, values, out_values, out_error);
}

bool hasSuffix(const QString& path, const QStringList& suffixes) {
  for (const QString& suffix : suffixes)
    if (!suffix.isEmpty() && path.endsWith('.' + suffix, Qt::CaseInsensitive))
      return true;
  return false;
}

QString suffixesText(const QStringList& suffixes) {
  QStringList dotted;
  for (const QString& suffix : suffixes)
    dotted << '.' + suffix;
  if (dotted.size() < 2)
    return dotted.join(QString());
  const QString last = dotted.takeLast();
  return dotted.join(QStringLiteral(", ")) + QStringLiteral(" or ") + last;
}

QString withSuffix(const QString& path, const QString& suffix, const QStringList& suffixes) {
  return hasSuffix(path, suffixes) ? path : path + '.' + suffix;
}

} // namespace mlod
