#pragma once
// Where exporter plugins are searched (docs/architecture.md section 8): every folder of the
// MOTIONLOD_PLUGIN_PATH environment variable (':'-separated), then
// <executable dir>/../<libdir>/motionlod/plugins, the same relative path in the build
// tree, a .deb and an unpacked .tgz.

#include <QString>
#include <QStringList>

namespace mlod {

// The relative path from an executable's folder to the plugin folder, fixed at configure time.
QString pluginRelativePath();

// The folders to search, in order, for an executable living in `executableDir`
// (QCoreApplication::applicationDirPath() in a running program). Duplicates removed.
QStringList pluginSearchPaths(const QString& executableDir);

} // namespace mlod
