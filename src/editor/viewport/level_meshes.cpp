#include "editor/viewport/level_meshes.h"

#include "core/lod/lod_package.h"
#include "core/project_package.h"
#include "editor/document/document.h"

#include <QElapsedTimer>
#include <QtConcurrent/QtConcurrentRun>

#include <algorithm>

namespace mlod {

bool LevelMeshes::Key::operator==(const Key& other) const {
  return character == other.character && characterIndex == other.characterIndex && level == other.level &&
         threshold == other.threshold && meshRatio == other.meshRatio && jpc.alpha == other.jpc.alpha &&
         jpc.mode == other.jpc.mode && jpc.zeroLength == other.jpc.zeroLength && jpc.joints == other.jpc.joints &&
         mappings == other.mappings && motions == other.motions;
}

LevelMeshes::LevelMeshes(Document* document, QObject* parent) : QObject(parent), m_document(document) {
  connect(&m_watcher, &QFutureWatcher<std::shared_ptr<Level>>::finished, this, &LevelMeshes::onFinished);
  connect(document, &Document::waitedJobChanged, this, &LevelMeshes::waitedJobChanged);
}

void LevelMeshes::waitedJobChanged(bool running) {
  if (running) {
    if (m_watcher.isRunning() && !m_waiting) { // built again when the job ends
      m_waiting = std::make_unique<Key>(m_running);
      if (m_cancel)
        m_cancel->store(true);
    }
    return;
  }
  if (m_waiting && !m_watcher.isRunning()) {
    const Key next = *m_waiting;
    m_waiting.reset();
    start(next);
  }
}

LevelMeshes::~LevelMeshes() {
  if (m_cancel)
    m_cancel->store(true);
  m_watcher.waitForFinished();
}

LevelMeshes::Key LevelMeshes::keyOf(int character, int level) const {
  const Project& project = m_document->project();
  Key key;
  key.characterIndex = character;
  key.level = level;
  const LodSet& lods = lodSetFor(project, character); // what the character's package is built with
  if (character < 0 || character >= m_document->assetCount() || level <= 0 || level >= int(lods.levels.size()))
    return key;
  key.character = m_document->asset(character);
  const LodLevel& spec = lods.levels[std::size_t(level)];
  key.threshold = spec.motionThreshold;
  key.meshRatio = spec.meshRatio;
  key.jpc = project.jpcSettings(character, key.character ? key.character->unitScale : 1.0);
  for (const ProjectMapping& mapping : project.mappings)
    if (mapping.character == character) {
      key.mappings.push_back(mapping);
      key.motions.push_back(mapping.motion >= 0 && mapping.motion < m_document->assetCount()
                                ? m_document->asset(mapping.motion)
                                : nullptr);
    }
  return key;
}

std::shared_ptr<const LevelMeshes::Level> LevelMeshes::request(int character, int level) {
  const Key key = keyOf(character, level);
  const auto kept = std::find_if(m_kept.begin(), m_kept.end(), [&](const Kept& k) { return k.key == key; });
  if (kept != m_kept.end())
    return kept->level;
  if (m_document->isWaitedJobRunning()) { // started when the job ends
    m_waiting = std::make_unique<Key>(key);
    if (m_watcher.isRunning() && m_cancel)
      m_cancel->store(true);
    return nullptr;
  }
  if (m_watcher.isRunning()) {
    if (!(m_running == key)) { // the latest request is what is in view: the running one is not
      if (m_cancel)
        m_cancel->store(true);
      m_waiting = std::make_unique<Key>(key);
    }
    return nullptr;
  }
  start(key);
  return nullptr;
}

void LevelMeshes::start(const Key& key) {
  m_running = key;
  m_waiting.reset();
  m_cancel = std::make_shared<std::atomic<bool>>(false);
  // what the worker reads: copies and shared assets, never the document
  std::vector<std::shared_ptr<const Asset>> assets;
  for (int i = 0; i < m_document->assetCount(); ++i)
    assets.push_back(m_document->asset(i));
  m_watcher.setFuture(QtConcurrent::run([project = m_document->project(), assets = std::move(assets),
                                         character = key.characterIndex, level = key.level, cancel = m_cancel]() {
    QElapsedTimer clock;
    clock.start();
    auto out = std::make_shared<Level>();
    std::vector<const Asset*> imported;
    for (const std::shared_ptr<const Asset>& asset : assets)
      imported.push_back(asset.get());
    const int levels[1] = {level};
    Result<LodPackage> package = buildLodPackage(project, imported, character, levels, {}, cancel.get());
    if (!package) {
      out->error = QString::fromStdString(package.message());
    } else if (std::optional<SkinnedMesh> mesh = levelMeshOnFullSkeleton(package->levels.front())) {
      out->mesh = std::move(*mesh);
      out->joints = package->levels.front().skeleton().jointCount();
    } else {
      out->error = tr("the level has no mesh");
    }
    out->seconds = double(clock.nsecsElapsed()) / 1e9;
    return out;
  }));
}

void LevelMeshes::onFinished() {
  const std::shared_ptr<Level> built = m_watcher.result();
  const bool cancelled = m_cancel && m_cancel->load();
  if (built && !cancelled) {
    ++m_builds;
    m_kept.push_back({m_running, built});
    if (m_kept.size() > kMaxKept)
      m_kept.erase(m_kept.begin());
  }
  const Key finished = m_running;
  if (m_waiting && !m_document->isWaitedJobRunning()) {
    const Key next = *m_waiting;
    m_waiting.reset();
    if (std::none_of(m_kept.begin(), m_kept.end(), [&](const Kept& k) { return k.key == next; }))
      start(next);
    else
      emit ready(next.characterIndex, next.level);
  }
  if (built && !cancelled)
    emit ready(finished.characterIndex, finished.level);
}

} // namespace mlod
