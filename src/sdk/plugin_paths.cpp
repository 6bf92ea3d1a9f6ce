#include "sdk/plugin_paths.h"

#include <QDir>
#include <QProcessEnvironment>

namespace mlod {

QString pluginRelativePath() {
  // bin/ -> ../<libdir>/motionlod/plugins; the number of ".." follows MLOD_BINDIR's depth.
  const int depth = QString(MLOD_BINDIR).split('/', Qt::SkipEmptyParts).size();
  QString up;
  for (int i = 0; i < depth; ++i)
    up += "../";
  return up + QStringLiteral(MLOD_PLUGIN_RELDIR);
}

QStringList pluginSearchPaths(const QString& executableDir) {
  QStringList paths;
  const QString env = QProcessEnvironment::systemEnvironment().value("MOTIONLOD_PLUGIN_PATH");
  for (const QString& dir : env.split(':', Qt::SkipEmptyParts))
    paths << QDir::cleanPath(dir);
  paths << QDir::cleanPath(QDir(executableDir).filePath(pluginRelativePath()));
  paths.removeDuplicates();
  return paths;
}

} // namespace mlod
