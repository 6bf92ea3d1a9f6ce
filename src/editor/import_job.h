#pragma once
// Imports a file off the UI thread, in the sandboxed import worker, with cancel.

#include "core/asset.h"
#include "io/import_options.h"

#include <QFutureWatcher>
#include <QObject>
#include <QString>

#include <atomic>
#include <memory>

namespace mlod {

class ImportJob : public QObject {
  Q_OBJECT
public:
  explicit ImportJob(QObject* parent = nullptr);
  ~ImportJob() override;

  bool isRunning() const;
  // Starts importing `path`; finished() or failed() follows, once.
  void start(const QString& path, const ImportOptions& options);
  // Asks the worker to stop; failed("import cancelled") follows.
  void cancel();

signals:
  void finished(const QString& path, std::shared_ptr<const mlod::Asset> asset);
  void failed(const QString& path, const QString& reason);

private:
  struct Outcome {
    std::shared_ptr<const Asset> asset;
    QString error;
  };
  QFutureWatcher<Outcome> m_watcher;
  std::shared_ptr<std::atomic<bool>> m_cancel;
  QString m_path;
};

} // namespace mlod
