#include "editor/document/asset_loader.h"

#include "editor/import_job.h"

namespace mlod {

AssetLoader::AssetLoader(QObject* parent) : QObject(parent), m_job(new ImportJob(this)) {
  connect(m_job, &ImportJob::finished, this, [this](const QString&, std::shared_ptr<const Asset> asset) {
    if (m_currentList == m_list)
      emit loaded(m_current, std::move(asset));
    next();
  });
  connect(m_job, &ImportJob::failed, this, [this](const QString& path, const QString& reason) {
    if (m_currentList == m_list) {
      m_failures += tr("%1 is missing: %2\n").arg(path, reason);
      emit failed(m_current, reason);
    }
    next();
  });
}

bool AssetLoader::isLoading() const {
  return m_active || m_job->isRunning();
}

void AssetLoader::load(std::vector<Item> items) {
  ++m_list;
  m_queue.assign(items.begin(), items.end());
  m_failures.clear();
  m_active = true;
  if (m_job->isRunning())
    m_job->cancel(); // its result belongs to the old list; next() follows when it stops
  else
    next();
}

void AssetLoader::next() {
  if (m_job->isRunning())
    return;
  if (m_queue.empty()) {
    if (m_active) {
      m_active = false;
      emit finished(m_failures.trimmed());
    }
    return;
  }
  m_current = m_queue.front();
  m_currentList = m_list;
  m_queue.pop_front();
  m_job->start(m_current.path, m_current.options);
}

} // namespace mlod
