#pragma once
// The exporter plugin host (docs/architecture.md section 8): finds exporter plugins, reads each one's
// metadata before loading it, checks the interface, and reports every failure instead of
// stopping at the first.
//
// Search order: static plugins linked into the program (Q_IMPORT_PLUGIN), then every folder
// of `folders` in order (pluginSearchPaths(): MOTIONLOD_PLUGIN_PATH, then
// <executable dir>/../<libdir>/motionlod/plugins). In a folder every library file is tried,
// in name order. The first plugin with an id wins; a later one with the same id is a
// failure ("duplicate id"). A failure is a file and a reason:
//  - not a plugin: no Qt plugin metadata in the file (or not a library Qt can read);
//  - another interface: its IID is not org.motionlod.Exporter/1;
//  - old (or newer) interface version: its metadata's interfaceVersion is not 1;
//  - no id / bad metadata;
//  - cannot load: the dynamic linker refused it (a missing symbol ...); every symbol is
//    resolved at load time, so a broken plugin fails here and not in the middle of an export;
//  - does not implement mlod::Exporter, or its id() differs from its metadata's id.

#include "sdk/exporter.h"

#include <QJsonObject>
#include <QList>
#include <QString>
#include <QStringList>

#include <memory>
#include <vector>

class QPluginLoader;

namespace mlod {

struct PluginInfo {
  QString id;
  QString name;
  QString version;
  QStringList suffixes;
  QString file; // the library it came from; ":static" for a static plugin
};

struct PluginFailure {
  QString file;
  QString reason;
};

class PluginHost {
public:
  PluginHost();
  ~PluginHost();
  PluginHost(const PluginHost&) = delete;
  PluginHost& operator=(const PluginHost&) = delete;

  // The folders a program searches: pluginSearchPaths(QCoreApplication::applicationDirPath()).
  static QStringList defaultFolders();

  // Loads the static plugins and those of `folders` (see above). Call once.
  void load(const QStringList& folders);
  // load(defaultFolders()).
  void loadDefault() { load(defaultFolders()); }

  const QList<PluginInfo>& plugins() const { return m_plugins; } // in load order
  const QList<PluginFailure>& failures() const { return m_failures; }
  const QStringList& folders() const { return m_folders; }
  // The exporter with this id, or null. The host owns it; it lives as long as the host.
  Exporter* exporter(const QString& id) const;

private:
  // Checks a plugin's metadata (QPluginLoader::metaData() / QStaticPlugin::metaData()).
  bool checkMetaData(const QString& file, const QJsonObject& metaData, PluginInfo& out_info);
  void add(const PluginInfo& info, QObject* instance);

  QStringList m_folders;
  QList<PluginInfo> m_plugins;
  QList<PluginFailure> m_failures;
  std::vector<Exporter*> m_exporters; // parallel to m_plugins
  std::vector<std::unique_ptr<QPluginLoader>> m_loaders;
};

} // namespace mlod
