#include "sdk/plugin_host.h"

#include "sdk/plugin_paths.h"

#include <QCoreApplication>
#include <QDir>
#include <QFileInfo>
#include <QJsonArray>
#include <QJsonObject>
#include <QLibrary>
#include <QPluginLoader>

namespace mlod {

PluginHost::PluginHost() = default;
PluginHost::~PluginHost() = default; // plugins stay loaded until the process ends (Qt's rule)

QStringList PluginHost::defaultFolders() {
  return pluginSearchPaths(QCoreApplication::applicationDirPath());
}

bool PluginHost::checkMetaData(const QString& file, const QJsonObject& metaData, PluginInfo& out_info) {
  const auto fail = [&](const QString& reason) {
    m_failures.append({file, reason});
    return false;
  };
  if (metaData.isEmpty())
    return fail(QStringLiteral("not a Qt plugin (no plugin metadata)"));
  const QString iid = metaData.value("IID").toString();
  if (iid != QLatin1String(kExporterIid)) {
    if (iid.startsWith(QLatin1String("org.motionlod.Exporter/")))
      return fail(QStringLiteral("built for interface %1; this host needs %2").arg(iid, QLatin1String(kExporterIid)));
    return fail(QStringLiteral("not an exporter plugin (IID '%1', expected '%2')").arg(iid, QLatin1String(kExporterIid)));
  }
  const QJsonObject data = metaData.value("MetaData").toObject();
  if (!data.contains("interfaceVersion"))
    return fail(QStringLiteral("no interfaceVersion in its metadata (built without add_exporter_plugin?)"));
  const int version = data.value("interfaceVersion").toInt(-1);
  if (version < kExporterInterfaceVersion)
    return fail(QStringLiteral("old interface version %1; this host needs %2: rebuild the plugin")
                    .arg(version)
                    .arg(kExporterInterfaceVersion));
  if (version > kExporterInterfaceVersion)
    return fail(QStringLiteral("interface version %1 is newer than this host's %2: update Motion LOD Studio")
                    .arg(version)
                    .arg(kExporterInterfaceVersion));
  out_info.id = data.value("id").toString();
  out_info.name = data.value("name").toString();
  out_info.version = data.value("version").toString();
  out_info.suffixes.clear();
  for (const QJsonValue& suffix : data.value("suffixes").toArray())
    out_info.suffixes << suffix.toString();
  out_info.file = file;
  if (out_info.id.isEmpty())
    return fail(QStringLiteral("no id in its metadata"));
  if (out_info.suffixes.isEmpty())
    return fail(QStringLiteral("no file suffixes in its metadata"));
  if (exporter(out_info.id)) {
    QString first;
    for (const PluginInfo& loaded : m_plugins)
      if (loaded.id == out_info.id)
        first = loaded.file;
    return fail(QStringLiteral("duplicate id '%1' (already loaded from %2)").arg(out_info.id, first));
  }
  return true;
}

void PluginHost::add(const PluginInfo& info, QObject* instance) {
  Exporter* exporter = qobject_cast<Exporter*>(instance);
  if (!exporter) {
    m_failures.append({info.file, QStringLiteral("does not implement mlod::Exporter")});
    return;
  }
  if (exporter->id() != info.id) {
    m_failures.append(
        {info.file, QStringLiteral("its id() '%1' differs from its metadata's id '%2'").arg(exporter->id(), info.id)});
    return;
  }
  m_plugins.append(info);
  m_exporters.push_back(exporter);
}

void PluginHost::load(const QStringList& folders) {
  m_folders = folders;
  const QList<QStaticPlugin> statics = QPluginLoader::staticPlugins();
  for (const QStaticPlugin& plugin : statics) {
    PluginInfo info;
    if (plugin.metaData().value("IID").toString() != QLatin1String(kExporterIid) &&
        !plugin.metaData().value("IID").toString().startsWith(QLatin1String("org.motionlod.")))
      continue; // another kind of static plugin (Qt's own): not ours to judge
    if (checkMetaData(QStringLiteral(":static"), plugin.metaData(), info))
      add(info, plugin.instance());
  }
  for (const QString& folder : folders) {
    const QDir dir(folder);
    if (!dir.exists())
      continue;
    const QFileInfoList entries = dir.entryInfoList(QDir::Files | QDir::NoDotAndDotDot, QDir::Name);
    for (const QFileInfo& entry : entries) {
      const QString file = entry.absoluteFilePath();
      if (!QLibrary::isLibrary(file))
        continue;
      auto loader = std::make_unique<QPluginLoader>(file);
      loader->setLoadHints(QLibrary::ResolveAllSymbolsHint); // a missing symbol fails now, not mid-export
      PluginInfo info;
      const QJsonObject metaData = loader->metaData();
      if (metaData.isEmpty()) {
        m_failures.append({file, QStringLiteral("not a Qt plugin: %1").arg(loader->errorString())});
        continue;
      }
      if (!checkMetaData(file, metaData, info))
        continue;
      if (!loader->load()) {
        m_failures.append({file, QStringLiteral("cannot load: %1").arg(loader->errorString())});
        continue;
      }
      QObject* instance = loader->instance();
      if (!instance) {
        m_failures.append({file, QStringLiteral("cannot create the plugin: %1").arg(loader->errorString())});
        continue;
      }
      add(info, instance);
      m_loaders.push_back(std::move(loader));
    }
  }
}

Exporter* PluginHost::exporter(const QString& id) const {
  for (qsizetype i = 0; i < m_plugins.size(); ++i)
    if (m_plugins[i].id == id)
      return m_exporters[std::size_t(i)];
  return nullptr;
}

} // namespace mlod
