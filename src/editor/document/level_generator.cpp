#include "editor/document/level_generator.h"

#include "core/project_package.h"
#include "editor/document/document.h"
#include "editor/document/edits.h"

#include <QPointer>
#include <QtConcurrent/QtConcurrentRun>
#include <cmath>

namespace mlod {

LevelGenerator::LevelGenerator(Document* document) : QObject(document), m_document(document) {
  connect(&m_watcher, &QFutureWatcherBase::finished, this, &LevelGenerator::onDone);
}

LevelGenerator::~LevelGenerator() {
  if (m_cancel)
    m_cancel->store(true);
  m_watcher.waitForFinished();
  // (a job still waited for goes with the document: it is being destroyed, no one to tell)
}

void LevelGenerator::setWaitedFor(bool waited) {
  if (waited == m_waitedFor)
    return;
  m_waitedFor = waited;
  if (waited)
    m_document->beginWaitedJob();
  else
    m_document->endWaitedJob();
}

int LevelGenerator::budgetAsset() const {
  const int owner = m_document->lodSetOwnerInView(); // the character the motion in view is viewed on
  return owner >= 0 ? owner : m_document->currentAsset();
}

bool LevelGenerator::start(double pixels, int levels, QString* out_error) {
  return launch(pixels, levels, m_document->lods().projection, m_document->lods().skinning, true, out_error);
}

bool LevelGenerator::preview(double pixels, int levels, const LodProjection& projection, LodSkinning skinning,
                             QString* out_error) {
  return launch(pixels, levels, projection, skinning, false, out_error);
}

bool LevelGenerator::launch(double pixels, int levels, const LodProjection& projection, LodSkinning skinning, bool land,
                            QString* out_error) {
  const auto refuse = [&](const QString& reason) {
    if (out_error)
      *out_error = reason;
    return false;
  };
  const int index = budgetAsset();
  const Asset* character = index >= 0 ? m_document->asset(index).get() : nullptr;
  if (!character)
    return refuse(tr("no asset in view"));
  if (m_watcher.isRunning())
    return refuse(tr("the previous generation is still running"));
  if (!(pixels > 0.0) || !std::isfinite(pixels) || levels < 1)
    return refuse(tr("a budget is > 0 pixels and at least one level"));
  if (Error error = projection.validate())
    return refuse(QString::fromStdString(error.message()));
  const Project& project = m_document->project();
  LodBudgetOptions options;
  options.jpc = project.jpcSettings(index, character->unitScale);
  options.projection = projection;
  options.skinning = skinning;
  std::vector<std::shared_ptr<const Asset>> assets; // kept alive while the worker runs
  for (int i = 0; i < m_document->assetCount(); ++i)
    assets.push_back(m_document->asset(i));
  m_cancel = std::make_shared<std::atomic<bool>>(false);
  m_running = true;
  m_land = land;
  setWaitedFor(true); // the views' background builds wait for it (Document::isWaitedJobRunning())
  m_pending = {};
  m_pending.asset = index;
  m_pending.pixels = pixels;
  m_pending.levels = levels;
  // The worker's progress reaches the UI thread queued, once per whole percent; a report
  // still queued when this object goes is dropped with it.
  auto lastPercent = std::make_shared<std::atomic<int>>(-1);
  QPointer<LevelGenerator> self(this);
  const auto report = [self, lastPercent, cancel = m_cancel](double fraction) {
    const int percent = static_cast<int>(std::floor(100.0 * fraction));
    if (lastPercent->exchange(percent) != percent && !cancel->load())
      QMetaObject::invokeMethod(
          self.data(),
          [self, percent, cancel] {
            if (self && !cancel->load())
              emit self->progressed(percent);
          },
          Qt::QueuedConnection);
    return !cancel->load();
  };
  // One character's search is kept (about 100 MB for a 5,000-triangle character with a
  // 4,500-frame clip): previewing another character lets the previous one's go.
  std::erase_if(m_caches, [index](const auto& entry) { return entry.first != index; });
  std::shared_ptr<LodBudgetCache>& cache = m_caches[index];
  if (!cache)
    cache = std::make_shared<LodBudgetCache>();
  m_watcher.setFuture(QtConcurrent::run(
      [project, assets, index, options, pixels, levels, report, cache, cancel = m_cancel, hook = m_hook]() mutable {
        auto out = std::make_shared<Outcome>();
        if (hook)
          hook(*cancel);
        if (cancel->load())
          return out;
        // Motions assigned to this character play on it too: every level must hold for them.
        std::vector<const Asset*> imported;
        for (const auto& asset : assets)
          imported.push_back(asset.get());
        Result<std::vector<Clip>> clips = assignedClips(project, imported, index);
        if (!clips) {
          out->lods = clips.error();
          return out;
        }
        options.clips = *clips;
        options.progress = report;
        options.cancel = cancel.get(); // the search's own loops stop within a fraction of a second
        options.cache = cache.get();   // (one generation at a time: no other worker uses it)
        out->lods = LodSet::fromPixelBudget(*assets[std::size_t(index)], pixels, levels, options, &out->report);
        return out;
      }));
  return true;
}

void LevelGenerator::cancel() {
  if (!m_running)
    return;
  m_cancel->store(true);
  m_running = false;
  setWaitedFor(false);
  if (m_land) {
    emit m_document->message(tr("Level generation cancelled; the levels are as they were"));
    emit finished(false, tr("cancelled"));
  } else {
    emit previewed(false, tr("cancelled"));
  }
}

void LevelGenerator::onDone() {
  const std::shared_ptr<Outcome> result = m_watcher.result();
  if (!m_running || (m_cancel && m_cancel->load()))
    return; // cancelled: already reported, the result is dropped
  m_running = false;
  setWaitedFor(false);
  if (!result || !result->lods) {
    const QString reason = result ? QString::fromStdString(result->lods.message()) : tr("no result");
    if (m_land) {
      emit m_document->message(tr("warning: level generation: %1").arg(reason));
      emit finished(false, reason);
    } else {
      emit previewed(false, reason);
    }
    return;
  }
  if (m_land) {
    land(result->lods.value(), m_pending.pixels, m_pending.asset);
    return;
  }
  m_plan = std::move(m_pending);
  m_plan.lods = result->lods.value();
  m_plan.report = std::move(result->report);
  m_plan.overrides = overridesAboveGeneratedLevels(m_document->project(), m_plan.asset, m_plan.lods);
  m_plan.overrideCount = overrideCountFor(m_document->project(), m_plan.asset);
  emit previewed(true, tr("%n level(s)", nullptr, static_cast<int>(m_plan.lods.levels.size())));
}

bool LevelGenerator::apply(QString* out_error) {
  const auto refuse = [&](const QString& reason) {
    if (out_error)
      *out_error = reason;
    return false;
  };
  if (m_plan.lods.levels.empty())
    return refuse(tr("no preview to apply"));
  if (m_running)
    return refuse(tr("a generation is running"));
  if (m_plan.asset != budgetAsset())
    return refuse(tr("the preview was made for another asset"));
  land(m_plan.lods, m_plan.pixels, m_plan.asset);
  return true;
}

void LevelGenerator::land(const LodSet& lods, double pixels, int asset) {
  if (asset != budgetAsset()) { // the levels are that character's: never another's
    const QString why = tr("the levels were generated for another asset than the one in view; not applied");
    emit m_document->message(tr("warning: level generation: %1").arg(why));
    emit finished(false, why);
    return;
  }
  const QString text = tr("Generate %1 levels within %2 px").arg(lods.levels.size()).arg(pixels);
  edit::applyLevelEdit(*m_document, replaceLodLevels(m_document->lods(), lods), text);
  emit m_document->message(text);
  emit finished(true, text);
}

} // namespace mlod
