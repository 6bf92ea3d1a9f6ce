#pragma once
// Autosave and crash recovery: the document is written to a recovery file every few
// minutes and shortly after every change; a clean close removes it, so a recovery file
// found at start means the last session ended without one.

#include <QObject>
#include <QString>
#include <QTimer>

namespace mlod {

class Document;

class Autosave : public QObject {
  Q_OBJECT
public:
  // `path` empty: recovery.mlod in the application's local data folder.
  explicit Autosave(Document* document, QString path = {}, QObject* parent = nullptr);

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
  QTimer m_afterChange; // single shot: a change settles, then it is written
  QTimer m_period;
};

} // namespace mlod
