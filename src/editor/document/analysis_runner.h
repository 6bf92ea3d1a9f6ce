#pragma once
// Runs the core incremental analysis (core/jpc/jpc_analysis.h) of the clip in view off the UI
// thread, one job at a time: a request while a job runs waits behind it (only the latest
// counts), a request whose figures the current snapshot already holds runs nothing. Holds the
// latest snapshot. Cancelling a job that was computing an edit's figures asks the document
// to take that edit back (editCancelled()).

#include "core/jpc/jpc_analysis.h"

#include <QFutureWatcher>
#include <QObject>
#include <QString>
#include <atomic>
#include <functional>
#include <memory>
#include <optional>

namespace mlod {

class AnalysisRunner : public QObject {
  Q_OBJECT
public:
  // `requestOf` gives the request for the state at the moment a job starts (nullopt: no clip
  // in view).
  using RequestOf = std::function<std::optional<JpcAnalysisRequest>()>;
  // Runs on the worker before any clustering, with the cancel flag (a test hook).
  using WorkerHook = std::function<void(const std::atomic<bool>&)>;

  explicit AnalysisRunner(RequestOf requestOf, QObject* parent = nullptr);
  ~AnalysisRunner() override; // cancels and waits for the worker

  // The figures of the clip in view; null before the first job lands or after reset().
  std::shared_ptr<const JpcAnalysis> snapshot() const { return m_snapshot; }
  bool isRunning() const { return m_running; }
  double lastMilliseconds() const { return m_lastMs; } // from the request to the figures, ms

  // `fromEdit`: the state changed by an edit (cancelling the job takes it back).
  void request(bool fromEdit = false);
  void cancel();
  // Drops the snapshot (the next job reuses nothing).
  void reset() { m_snapshot.reset(); }
  // Cancels the running job and waits for it: the next request starts afresh.
  void stop();
  void setWorkerHook(WorkerHook hook) { m_hook = std::move(hook); }

signals:
  void started();
  void progress(int done, int total);
  void finished(bool ok, const QString& message); // ok = new figures in snapshot()
  void editCancelled();                           // before finished(false, "cancelled")
  void message(const QString& line);

private:
  void start();
  void onDone();

  RequestOf m_requestOf;
  WorkerHook m_hook;
  std::shared_ptr<const JpcAnalysis> m_snapshot;
  QFutureWatcher<std::shared_ptr<Result<std::shared_ptr<const JpcAnalysis>>>> m_watcher;
  std::shared_ptr<std::atomic<bool>> m_cancel;
  bool m_running = false;
  bool m_pending = false;
  bool m_jobFromEdit = false;     // the running job computes the figures of the last edit
  bool m_pendingFromEdit = false; // likewise for the request waiting behind it
  qint64 m_requestedAt = 0;
  double m_lastMs = 0.0;
};

} // namespace mlod
