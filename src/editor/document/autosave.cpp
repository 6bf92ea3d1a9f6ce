#include "editor/document/autosave.h"

#include "editor/document/document.h"

#include <QDir>
#include <QFile>
#include <QStandardPaths>

namespace mlod {

namespace {

constexpr int kRecoverySlots = 16;

QString slotPath(const QString& folder, int slot) {
  const QString name = slot == 1 ? QStringLiteral("recovery") : QStringLiteral("recovery-%1").arg(slot);
  return QDir(folder).filePath(name + kProjectSuffix);
}

} // namespace

Autosave::Autosave(Document* document, QString path, QObject* parent)
    : QObject(parent), m_document(document), m_path(std::move(path)) {
  if (m_path.isEmpty()) {
    const QString folder = QStandardPaths::writableLocation(QStandardPaths::AppLocalDataLocation);
    QDir().mkpath(folder);
    // The first slot no running studio holds, unless a later free one holds a recovery (its
    // studio crashed): that one, so that the work is offered. A lock is stale only once its
    // process has gone (stale time 0: never by age).
    for (int slot = 1; slot <= kRecoverySlots; ++slot) {
      auto lock = std::make_unique<QLockFile>(slotPath(folder, slot) + ".lock");
      lock->setStaleLockTime(0);
      if (!lock->tryLock(0))
        continue;
      const bool recovery = QFile::exists(slotPath(folder, slot));
      if (!m_lock || recovery) {
        m_lock = std::move(lock); // (a first free slot held so far is released here)
        m_path = slotPath(folder, slot);
      }
      if (recovery)
        break;
    }
    if (m_path.isEmpty()) // every slot held: the last one, shared
      m_path = slotPath(folder, kRecoverySlots);
  }
  m_afterChange.setSingleShot(true);
  setDelays(2000, 3 * 60 * 1000);
  connect(&m_afterChange, &QTimer::timeout, this, &Autosave::saveNow);
  connect(&m_period, &QTimer::timeout, this, &Autosave::saveNow);
  connect(document->undoStack(), &QUndoStack::indexChanged, this, [this] { m_afterChange.start(); });
  m_period.start();
}

Autosave::~Autosave() = default; // the slot's lock goes with it

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
