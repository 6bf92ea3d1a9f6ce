#include "editor/import_job.h"

#include <QtConcurrent>

namespace mlod {

ImportJob::ImportJob(QObject* parent) : QObject(parent) {
  connect(&m_watcher, &QFutureWatcherBase::finished, this, [this] {
    const Outcome outcome = m_watcher.result();
    if (outcome.asset)
      emit finished(m_path, outcome.asset);
    else
      emit failed(m_path, outcome.error);
  });
}

ImportJob::~ImportJob() {
  cancel();
  m_watcher.waitForFinished();
}

bool ImportJob::isRunning() const { return m_watcher.isRunning(); }

void ImportJob::start(const QString& path, const ImportOptions& options) {
  Q_ASSERT(!isRunning());
  m_path = path;
  m_cancel = std::make_shared<std::atomic<bool>>(false);
  const std::string file = path.toStdString();
  m_watcher.setFuture(QtConcurrent::run([file, options, limits = m_limits, cancel = m_cancel]() mutable -> Outcome {
    limits.cancel = cancel.get();
    Result<Asset> result = importAssetIsolated(file, options, limits);
    if (!result)
      return {nullptr, QString::fromStdString(result.message())};
    return {std::make_shared<const Asset>(std::move(result).value()), {}};
  }));
}

void ImportJob::cancel() {
  if (m_cancel)
    m_cancel->store(true);
}

} // namespace mlod
