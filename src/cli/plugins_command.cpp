#include "cli/plugins_command.h"

#include "sdk/plugin_host.h"

#include <CLI/CLI.hpp>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QJsonValue>

#include <cstdio>
#include <iostream>

namespace mlod::cli {

void PluginsCommand::attach(CLI::App& app) {
  CLI::App* command = app.add_subcommand("plugins", "List the exporter plugins and those that failed to load");
  command->add_flag("--json", json, "print one JSON document on stdout");
}

int PluginsCommand::run() const {
  PluginHost host;
  host.loadDefault();
  if (json) {
    QJsonArray plugins;
    for (const PluginInfo& info : host.plugins()) {
      QJsonArray options;
      for (const ExporterOption& option : host.exporter(info.id)->options())
        options.append(QJsonObject{{"key", option.key},
                                   {"type", toString(option.type)},
                                   {"default", QJsonValue::fromVariant(option.defaultValue)},
                                   {"minimum", QJsonValue::fromVariant(option.minimum)},
                                   {"maximum", QJsonValue::fromVariant(option.maximum)},
                                   {"choices", QJsonArray::fromStringList(option.choices)},
                                   {"help", option.help}});
      plugins.append(QJsonObject{{"id", info.id},
                                 {"name", info.name},
                                 {"version", info.version},
                                 {"suffixes", QJsonArray::fromStringList(info.suffixes)},
                                 {"file", info.file},
                                 {"options", options}});
    }
    QJsonArray failed;
    for (const PluginFailure& failure : host.failures())
      failed.append(QJsonObject{{"file", failure.file}, {"reason", failure.reason}});
    const QJsonObject doc{{"plugins", plugins},
                          {"failed", failed},
                          {"search_path", QJsonArray::fromStringList(host.folders())}};
    std::cout << QJsonDocument(doc).toJson(QJsonDocument::Indented).toStdString() << std::flush;
    return kExitOk;
  }
  std::printf("exporter plugins: %lld\n", static_cast<long long>(host.plugins().size()));
  for (const PluginInfo& info : host.plugins()) {
    std::printf("  %-10s %-32s %-8s .%s\n", qPrintable(info.id), qPrintable(info.name), qPrintable(info.version),
                qPrintable(info.suffixes.join(", .")));
    for (const ExporterOption& option : host.exporter(info.id)->options())
      std::printf("      --option %s=<%s> (default %s)  %s\n", qPrintable(option.key), toString(option.type),
                  qPrintable(option.defaultValue.toString()), qPrintable(option.help));
  }
  if (!host.failures().isEmpty()) {
    std::printf("failed to load: %lld\n", static_cast<long long>(host.failures().size()));
    for (const PluginFailure& failure : host.failures())
      std::printf("  %s: %s\n", qPrintable(failure.file), qPrintable(failure.reason));
  }
  std::printf("searched: %s\n", qPrintable(host.folders().join(":")));
  return kExitOk;
}

} // namespace mlod::cli
