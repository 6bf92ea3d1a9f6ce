#pragma once
// Autosave and crash recovery: the document is written to a recovery file every few
// minutes and shortly after every change; a clean close removes it, so a recovery file
// found at start means the session that wrote it ended without one. Each running studio
// holds its own recovery slot (recovery.mlod, recovery-2.mlod, ... locked while it runs),
// so two studios at once never overwrite or discard each other's recovery, and a new one
// takes over the slot of one that crashed.

#include <QLockFile>
#include <QObject>
#include <QString>
#include <QTimer>

#include <memory>

namespace mlod {

class Document;

class Autosave : public QObject {
  Q_OBJECT
public:
  // `path` empty: a free recovery slot in the application's local data folder (one left by
  // a studio that crashed first, so that its work is offered; else the first free one).
  explicit Autosave(Document* document, QString path = {}, QObject* parent = nullptr);
  ~Autosave() override;

  QString path() const { return m_path; }
  bool hasRecovery() const;
  // Writes the recovery file now (only when the document has unsaved changes).
  bool saveNow();
  void discard(); // removes the recovery file (clean close, or the user declined it)
  void setDelays(int afterChangeMs, int periodMs);

signals:
  void saved(const QString& path);

private:
  Document* m_document;
  QString m_path;
  std::unique_ptr<QLockFile> m_lock; // the slot's, while this studio runs (none for a given path)
  QTimer m_afterChange; // single shot: a change settles, then it is written
  QTimer m_period;
};

} // namespace mlod
