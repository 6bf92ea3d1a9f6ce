#include "editor/document/analysis_runner.h"

#include <QDateTime>
#include <QPointer>
#include <QtConcurrent/QtConcurrentRun>

namespace mlod {

using Outcome = Result<std::shared_ptr<const JpcAnalysis>>;

AnalysisRunner::AnalysisRunner(RequestOf requestOf, QObject* parent)
    : QObject(parent), m_requestOf(std::move(requestOf)) {
  connect(&m_watcher, &QFutureWatcherBase::finished, this, &AnalysisRunner::onDone);
}

AnalysisRunner::~AnalysisRunner() {
  if (m_cancel)
    m_cancel->store(true);
  m_watcher.waitForFinished();
}

void AnalysisRunner::request(bool fromEdit) {
  m_requestedAt = QDateTime::currentMSecsSinceEpoch();
  if (m_running) {
    m_pending = true;
    m_pendingFromEdit = m_pendingFromEdit || fromEdit;
    return;
  }
  m_pendingFromEdit = fromEdit;
  start();
}

void AnalysisRunner::cancel() {
  if (m_running && m_cancel)
    m_cancel->store(true);
}

void AnalysisRunner::stop() {
  cancel();
  m_watcher.waitForFinished();
  m_running = false;
  m_pending = false;
}

void AnalysisRunner::start() {
  m_pending = false;
  const std::optional<JpcAnalysisRequest> request = m_requestOf();
  if (!request) {
    m_snapshot.reset();
    emit finished(false, tr("no clip in view"));
    return;
  }
  if (m_snapshot && m_snapshot->answers(*request)) {
    emit finished(true, tr("figures unchanged"));
    return;
  }
  m_running = true;
  m_jobFromEdit = m_pendingFromEdit;
  m_pendingFromEdit = false;
  m_cancel = std::make_shared<std::atomic<bool>>(false);
  emit started();
  QPointer<AnalysisRunner> self(this);
  JpcAnalysisOptions options;
  options.progress = [self](int done, int total) {
    QMetaObject::invokeMethod(
        self.data(),
        [self, done, total] {
          if (self)
            emit self->progress(done, total);
        },
        Qt::QueuedConnection);
  };
  m_watcher.setFuture(QtConcurrent::run(
      [request = *request, previous = m_snapshot, cancel = m_cancel, hook = m_hook, options]() mutable {
        if (hook)
          hook(*cancel);
        options.cancel = cancel.get();
        return std::make_shared<Outcome>(buildJpcAnalysis(request, previous, options));
      }));
}

void AnalysisRunner::onDone() {
  if (!m_running)
    return; // stopped: the result is dropped
  m_running = false;
  const std::shared_ptr<Outcome> result = m_watcher.result();
  const bool cancelled = m_cancel && m_cancel->load();
  const bool ok = result && *result;
  if (ok && !cancelled) {
    m_snapshot = result->value();
    m_lastMs = static_cast<double>(QDateTime::currentMSecsSinceEpoch() - m_requestedAt);
  }
  if (m_pending && !cancelled) {
    start();
    return;
  }
  if (cancelled) {
    m_pending = false;
    const bool fromEdit = m_jobFromEdit;
    if (fromEdit)
      emit editCancelled(); // the document undoes the edit, which may start the job of its own figures
    m_jobFromEdit = false;  // those are no edit of their own: cancelling them takes nothing back
    emit message(fromEdit ? tr("Clustering cancelled; the last edit was taken back") : tr("Clustering cancelled"));
    emit finished(false, tr("cancelled"));
    return;
  }
  m_jobFromEdit = false;
  if (!ok) {
    const QString reason = result ? QString::fromStdString(result->message()) : tr("no result");
    emit message(tr("warning: clustering failed: %1").arg(reason));
    emit finished(false, reason);
    return;
  }
  const int pairs = m_snapshot->clusteredPairs; // none when the edit touched only locked joints
  const int cached = m_snapshot->reusedFromOtherLevels;
  emit finished(true, pairs == 0 && cached > 0
                          ? tr("figures from the cache: %1 joint clusterings of other levels reused, none run (%2 ms)")
                                .arg(cached)
                                .arg(m_lastMs)
                      : pairs == 0 ? tr("no joint clustered again (%1 ms)").arg(m_lastMs)
                      : pairs == 1 ? tr("1 joint clustering in %1 ms").arg(m_lastMs)
                                   : tr("%1 joint clusterings in %2 ms").arg(pairs).arg(m_lastMs));
}

} // namespace mlod
