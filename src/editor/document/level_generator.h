#pragma once
// Generates the LOD set of the asset in view from a pixel budget off the UI thread (core:
// LodSet::fromPixelBudget with the document's JPC settings and projection, playing the motions
// the project assigns to the asset too, project_package.h's assignedClips()). When it lands,
// the new levels are one undo step (per-joint overrides kept by level index). One generation
// at a time; cancelling drops the result at once and leaves the document as it was (the core
// call has no cancel point, so the worker finishes in the background: isBusy()).

#include "core/error.h"
#include "core/lod/lod_set.h"

#include <QFutureWatcher>
#include <QObject>
#include <QString>
#include <atomic>
#include <functional>
#include <memory>

namespace mlod {

class Document;

class LevelGenerator : public QObject {
  Q_OBJECT
public:
  using WorkerHook = std::function<void(const std::atomic<bool>&)>;
  explicit LevelGenerator(Document* document); // a child of the document
  ~LevelGenerator() override;                  // cancels and waits for the worker

  // Starts generating `levels` levels within `pixels` (> 0) on screen. Returns false with a
  // reason when no asset is in view, the budget is bad, or a worker still runs.
  bool start(double pixels, int levels, QString* out_error = nullptr);
  // Drops the running generation's result; finished(false, "cancelled") follows at once.
  void cancel();
  bool isRunning() const { return m_running; }                      // a generation whose result will count
  bool isBusy() const { return m_watcher.isRunning(); }             // a worker still runs (a cancelled one too)
  void setWorkerHook(WorkerHook hook) { m_hook = std::move(hook); } // test hook, before the generation

signals:
  // ok: the levels are in the document (one undo step named `message`); else the reason.
  void finished(bool ok, const QString& message);

private:
  void onDone();

  Document* m_document;
  QFutureWatcher<std::shared_ptr<Result<LodSet>>> m_watcher;
  std::shared_ptr<std::atomic<bool>> m_cancel;
  WorkerHook m_hook;
  bool m_running = false;
  QString m_text; // the undo text of the running generation
};

} // namespace mlod
