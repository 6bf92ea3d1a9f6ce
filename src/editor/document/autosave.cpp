#include "editor/document/autosave.h"

#include "editor/document/document.h"

#include <QDir>
#include <QFile>
#include <QStandardPaths>

namespace mlod {

Autosave::Autosave(Document* document, QString path, QObject* parent)
    : QObject(parent), m_document(document), m_path(std::move(path)) {
  if (m_path.isEmpty()) {
    const QString folder = QStandardPaths::writableLocation(QStandardPaths::AppLocalDataLocation);
    QDir().mkpath(folder);
    m_path = QDir(folder).filePath(QString("recovery") + kProjectSuffix);
  }
  m_afterChange.setSingleShot(true);
  setDelays(2000, 3 * 60 * 1000);
  connect(&m_afterChange, &QTimer::timeout, this, &Autosave::saveNow);
  connect(&m_period, &QTimer::timeout, this, &Autosave::saveNow);
  connect(document->undoStack(), &QUndoStack::indexChanged, this, [this] { m_afterChange.start(); });
  m_period.start();
}

void Autosave::setDelays(int afterChangeMs, int periodMs) {
  m_afterChange.setInterval(afterChangeMs);
  m_period.setInterval(periodMs);
}

bool Autosave::hasRecovery() const { return QFile::exists(m_path); }

bool Autosave::saveNow() {
  if (!m_document->isModified())
    return false;
  if (!m_document->saveRecovery(m_path))
    return false;
  emit saved(m_path);
  return true;
}

void Autosave::discard() {
  QFile::remove(m_path);
  QFile::remove(Document::recoveryOriginPath(m_path));
}

} // namespace mlod
