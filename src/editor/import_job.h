#pragma once
// Imports a file off the UI thread, in the sandboxed import worker, with cancel.

#include "core/asset.h"
#include "io/import_options.h"
#include "io/isolated_import.h"

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
  // Time and memory limits of the import worker (the cancel flag is the job's own).
  void setLimits(const IsolationLimits& limits) { m_limits = limits; }
  const IsolationLimits& limits() const { return m_limits; }
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
  IsolationLimits m_limits;
};

} // namespace mlod
