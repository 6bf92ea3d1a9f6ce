#include "editor/document/level_generator.h"

#include "core/project_package.h"
#include "editor/document/document.h"
#include "editor/document/edits.h"

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
}

bool LevelGenerator::start(double pixels, int levels, QString* out_error) {
  const auto refuse = [&](const QString& reason) {
    if (out_error)
      *out_error = reason;
    return false;
  };
  const Asset* character = m_document->currentAssetPtr();
  if (!character)
    return refuse(tr("no asset in view"));
  if (m_watcher.isRunning())
    return refuse(tr("the previous generation is still running"));
  if (!(pixels > 0.0) || !std::isfinite(pixels) || levels < 1)
    return refuse(tr("a budget is > 0 pixels and at least one level"));
  const Project& project = m_document->project();
  const int index = m_document->currentAsset();
  LodBudgetOptions options;
  options.jpc = project.jpcSettings(index, character->unitScale);
  options.projection = project.lods.projection;
  std::vector<std::shared_ptr<const Asset>> assets; // kept alive while the worker runs
  for (int i = 0; i < m_document->assetCount(); ++i)
    assets.push_back(m_document->asset(i));
  m_cancel = std::make_shared<std::atomic<bool>>(false);
  m_running = true;
  m_text = tr("Generate %1 levels within %2 px").arg(levels).arg(pixels);
  m_watcher.setFuture(
      QtConcurrent::run([project, assets, index, options, pixels, levels, cancel = m_cancel, hook = m_hook]() mutable {
        if (hook)
          hook(*cancel);
        if (cancel->load())
          return std::shared_ptr<Result<LodSet>>();
        // Motions assigned to this character play on it too: every level must hold for them.
        std::vector<const Asset*> imported;
        for (const auto& asset : assets)
          imported.push_back(asset.get());
        Result<std::vector<Clip>> clips = assignedClips(project, imported, index);
        if (!clips)
          return std::make_shared<Result<LodSet>>(clips.error());
        options.clips = *clips;
        return std::make_shared<Result<LodSet>>(
            LodSet::fromPixelBudget(*assets[std::size_t(index)], pixels, levels, options));
      }));
  return true;
}

void LevelGenerator::cancel() {
  if (!m_running)
    return;
  m_cancel->store(true);
  m_running = false;
  emit m_document->message(tr("Level generation cancelled; the levels are as they were"));
  emit finished(false, tr("cancelled"));
}

void LevelGenerator::onDone() {
  const std::shared_ptr<Result<LodSet>> result = m_watcher.result();
  if (!m_running || (m_cancel && m_cancel->load()))
    return; // cancelled: already reported, the result is dropped
  m_running = false;
  if (!result || !*result) {
    const QString reason = result ? QString::fromStdString(result->message()) : tr("no result");
    emit m_document->message(tr("warning: level generation: %1").arg(reason));
    emit finished(false, reason);
    return;
  }
  edit::applyLevelEdit(*m_document, replaceLodLevels(m_document->project().lods, result->value()), m_text);
  emit m_document->message(m_text);
  emit finished(true, m_text);
}

} // namespace mlod
