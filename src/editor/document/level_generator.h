#pragma once
// Generates the LOD set of the asset in view from a pixel budget off the UI thread (core:
// LodSet::fromPixelBudget with the document's JPC settings, playing the motions the project
// assigns to the asset too, project_package.h's assignedClips()). Two ways
// (docs/architecture.md section 7):
// - start(): generate and land at once (the stale-distances offer);
// - preview(), then apply(): the Budget dialog's way. The preview is the generator's whole
//   result (the set, LodBudgetReport, the overrides above its levels); apply() lands exactly
//   that set, so what the dialog shows is what the project gets.
// Either way the new levels are one undo step (per-joint overrides kept by level index).
// Each character's search keeps what it computed (core/lod/lod_budget_cache.h, one cache per
// asset index, checked against the inputs of each run): a preview asked again with another
// budget, level count, projection or skinning reuses the motions and meshes already made, and after a
// joint edit re-clusters that joint alone; the levels are the same as without it.
// One generation at a time; it reports its progress in percent and stops at the core's next
// cancel point after cancel(), which drops the result at once and leaves the document as it
// was (the worker may still run briefly: isBusy()). While a generation runs the views' own
// background builds wait (Document::isWaitedJobRunning()).

#include "core/error.h"
#include "core/lod/lod_levels.h"
#include "core/lod/lod_set.h"

#include <QFutureWatcher>
#include <QObject>
#include <QString>
#include <atomic>
#include <functional>
#include <map>
#include <memory>

namespace mlod {

class Document;

// What one generation made, before it lands.
struct LevelPlan {
  int asset = -1; // the asset it was made for
  double pixels = 0.0;
  int levels = 0; // asked for; lods may hold fewer (report.dropped says why)
  LodSet lods;
  LodBudgetReport report;
  std::vector<LodOverrideAbove> overrides; // overridesAboveGeneratedLevels(): above their level's E, or dropped
  int overrideCount = 0;                   // overrideCountFor(): every per-joint override of the set
};

class LevelGenerator : public QObject {
  Q_OBJECT
public:
  using WorkerHook = std::function<void(const std::atomic<bool>&)>;
  explicit LevelGenerator(Document* document); // a child of the document
  ~LevelGenerator() override;                  // cancels and waits for the worker

  // Starts generating up to `levels` levels within `pixels` (> 0) on screen under the
  // projection and skinning of the set in view (LodSet::skinning); they land when done
  // (finished()). Returns false with a reason when no asset is in view, the budget is bad,
  // or a worker still runs.
  bool start(double pixels, int levels, QString* out_error = nullptr);
  // The same under `projection`, for a character skinned where `skinning` says
  // (LodBudgetOptions::skinning), landing nothing: previewed() then plan().
  bool preview(double pixels, int levels, const LodProjection& projection, LodSkinning skinning,
               QString* out_error = nullptr);
  // The last successful preview (empty levels before one).
  const LevelPlan& plan() const { return m_plan; }
  // Lands plan() as one undo step (finished(true, ...)). Errors: no preview, a generation
  // running, or another asset in view than the plan's.
  bool apply(QString* out_error = nullptr);
  // Drops the running generation's result; finished() or previewed() (false, "cancelled")
  // follows at once.
  void cancel();
  bool isRunning() const { return m_running; }                      // a generation whose result will count
  bool isBusy() const { return m_watcher.isRunning(); }             // a worker still runs (a cancelled one too)
  void setWorkerHook(WorkerHook hook) { m_hook = std::move(hook); } // test hook, before the generation

signals:
  // ok: the levels are in the document (one undo step named `message`); else the reason.
  void finished(bool ok, const QString& message);
  // A preview ended: ok, plan() holds it; else the reason ("cancelled" after cancel()).
  void previewed(bool ok, const QString& message);
  // Percent done (0..100) of the running generation.
  void progressed(int percent);

private:
  struct Outcome {
    Result<LodSet> lods = Error("no result");
    LodBudgetReport report;
  };
  // The asset whose levels a budget makes: the one in view, or the character the motion in
  // view is viewed on, else mapped onto first (its set is the character's:
  // Document::lodSetOwnerInView()).
  int budgetAsset() const;
  bool launch(double pixels, int levels, const LodProjection& projection, LodSkinning skinning, bool land,
              QString* out_error);
  void onDone();
  void land(const LodSet& lods, double pixels, int asset);
  // Tells the document a generation the artist waits for runs, or no longer (once each way).
  void setWaitedFor(bool waited);

  Document* m_document;
  QFutureWatcher<std::shared_ptr<Outcome>> m_watcher;
  std::shared_ptr<std::atomic<bool>> m_cancel;
  WorkerHook m_hook;
  bool m_running = false;
  bool m_land = false; // the running generation lands when done (start()), else it is a preview
  bool m_waitedFor = false; // the document was told of the running generation (setWaitedFor())
  LevelPlan m_pending; // the running generation's request
  LevelPlan m_plan;
  std::map<int, std::shared_ptr<LodBudgetCache>> m_caches; // the last previewed asset's (by index); the worker's while it runs
};

} // namespace mlod
