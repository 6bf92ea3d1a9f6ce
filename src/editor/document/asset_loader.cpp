#include "editor/document/asset_loader.h"

#include "editor/import_job.h"

#include <QFileInfo>
#include <map>
#include <tuple>

namespace mlod {

namespace {
// The items in order of first appearance, one group per file and options: a file is known by
// its canonical path (another spelling or a link to it is the same file), a missing one by
// its path as given. Paths repeat, so each is resolved once.
std::deque<std::vector<AssetLoader::Item>> groupedByFile(std::vector<AssetLoader::Item> items) {
  std::map<QString, QString> canonical;
  std::map<std::tuple<QString, double, double>, std::size_t> groupOf;
  std::deque<std::vector<AssetLoader::Item>> groups;
  for (AssetLoader::Item& item : items) {
    auto [known, isNew] = canonical.try_emplace(item.path);
    if (isNew) {
      known->second = QFileInfo(item.path).canonicalFilePath();
      if (known->second.isEmpty())
        known->second = item.path;
    }
    const auto key = std::make_tuple(known->second, item.options.unitScale, item.options.fps);
    const auto [group, added] = groupOf.try_emplace(key, groups.size());
    if (added)
      groups.emplace_back();
    groups[group->second].push_back(std::move(item));
  }
  return groups;
}
} // namespace

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
  m_queue = groupedByFile(std::move(items));
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
  m_current = std::move(m_queue.front());
  m_currentList = m_list;
  m_queue.pop_front();
  ++m_imports;
  m_job->start(m_current.front().path, m_current.front().options);
}

} // namespace mlod
