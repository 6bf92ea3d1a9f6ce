#include "editor/document/document.h"

#include "editor/document/commands.h"
#include "editor/import_job.h"

#include <QDateTime>
#include <QDir>
#include <QFileInfo>
#include <QSaveFile>
#include <QtConcurrent>

#include <algorithm>
#include <limits>
#include <numeric>

namespace mlod {

Document::Document(QObject* parent)
    : QObject(parent), m_undo(new QUndoStack(this)), m_loader(new ImportJob(this)), m_reimport(new ImportJob(this)) {
  connect(m_reimport, &ImportJob::finished, this, [this](const QString& path, std::shared_ptr<const Asset> asset) {
    const int index = m_reimportIndex;
    m_reimportIndex = -1;
    if (index < 0 || index >= assetCount() || assetFilePath(index) != path) {
      emit unitScaleChanged(false, tr("the asset changed while it was imported again"));
      return;
    }
    ProjectAsset after = m_project.assets[std::size_t(index)];
    after.unitScale = m_reimportScale;
    m_undo->push(new ReplaceAsset(this, index, m_project.assets[std::size_t(index)], m_assets[std::size_t(index)], after,
                                  asset, tr("Set unit of %1 to %2 cm").arg(QFileInfo(path).fileName()).arg(asset->unitScale)));
    emit unitScaleChanged(true, tr("%1: %2 cm per file unit").arg(path).arg(asset->unitScale));
  });
  connect(m_reimport, &ImportJob::failed, this, [this](const QString& path, const QString& reason) {
    m_reimportIndex = -1;
    emit message(tr("warning: %1: %2").arg(path, reason));
    emit unitScaleChanged(false, reason);
  });
  connect(&m_watcher, &QFutureWatcherBase::finished, this, &Document::onAnalysisDone);
  connect(&m_levelsWatcher, &QFutureWatcherBase::finished, this, &Document::onLevelsGenerated);
  connect(m_loader, &ImportJob::finished, this, [this](const QString& path, std::shared_ptr<const Asset> asset) {
    if (!m_toLoad.empty()) {
      const int index = m_toLoad.front();
      m_toLoad.erase(m_toLoad.begin());
      m_assets[static_cast<std::size_t>(index)] = std::move(asset);
      emit message(tr("Loaded %1").arg(path));
      emit assetsChanged();
      if (index == currentAsset() || currentAsset() < 0) {
        if (currentAsset() < 0)
          m_project.view.asset = index;
        requestAnalysis();
        emit currentChanged();
      }
    }
    importNextMissing();
  });
  connect(m_loader, &ImportJob::failed, this, [this](const QString& path, const QString& reason) {
    if (!m_toLoad.empty())
      m_toLoad.erase(m_toLoad.begin());
    emit message(tr("warning: %1: %2 (relink it in the Assets dock)").arg(path, reason));
    m_openMessage += tr("%1 is missing: %2\n").arg(path, reason);
    importNextMissing();
  });
}

Document::~Document() {
  if (m_cancel)
    m_cancel->store(true);
  m_watcher.waitForFinished();
  if (m_levelsCancel)
    m_levelsCancel->store(true);
  m_levelsWatcher.waitForFinished();
}

QString Document::assetFilePath(int index) const {
  const std::string& stored = m_project.assets[static_cast<std::size_t>(index)].path;
  if (m_fileName.isEmpty())
    return QFileInfo(QString::fromStdString(stored)).absoluteFilePath();
  return QString::fromStdString(resolveAssetPath(m_fileName.toStdString(), stored).string());
}

const Asset* Document::currentAssetPtr() const {
  const int index = currentAsset();
  return index >= 0 && index < assetCount() ? m_assets[static_cast<std::size_t>(index)].get() : nullptr;
}

const Clip* Document::currentClipPtr() const {
  const Asset* a = currentAssetPtr();
  if (!a || currentClip() < 0 || currentClip() >= static_cast<int>(a->clips.size()))
    return nullptr;
  return &a->clips[static_cast<std::size_t>(currentClip())];
}

void Document::setCurrentAsset(int asset, int clip) {
  if (asset == currentAsset() && clip == currentClip())
    return;
  m_project.view.asset = asset;
  m_project.view.clip = clip;
  m_currentJoint = -1;
  m_project.view.joint.clear();
  m_analysis.reset();
  requestAnalysis();
  emit currentChanged();
}

void Document::setCurrentLevel(int level) {
  level = std::clamp(level, 0, m_project.levelCount() - 1);
  if (level == currentLevel())
    return;
  m_project.view.level = level;
  emit currentChanged();
}

void Document::setCurrentJoint(int joint) {
  if (joint == m_currentJoint)
    return;
  m_currentJoint = joint;
  m_project.view.joint = jointName(joint);
  emit currentChanged();
}

std::string Document::jointName(int joint) const {
  const Asset* a = currentAssetPtr();
  return a && joint >= 0 && joint < a->skeleton.jointCount() ? a->skeleton.joints[static_cast<std::size_t>(joint)].name
                                                              : std::string();
}

// ---- intents ------------------------------------------------------------------------

void Document::addAsset(std::shared_ptr<const Asset> asset, const QString& path, double unitScale) {
  ProjectAsset entry;
  entry.path = QFileInfo(path).absoluteFilePath().toStdString();
  if (!m_fileName.isEmpty())
    entry.path = storedAssetPath(m_fileName.toStdString(), entry.path);
  entry.unitScale = unitScale;
  m_undo->push(new ChangeAssets(this, assetCount(), std::move(entry), std::move(asset), false));
}

void Document::removeAsset(int index) {
  if (index < 0 || index >= assetCount())
    return;
  m_undo->push(new ChangeAssets(this, index, m_project.assets[static_cast<std::size_t>(index)],
                                m_assets[static_cast<std::size_t>(index)], true));
}

void Document::setAlpha(double alpha) {
  if (alpha != m_project.alpha && std::isfinite(alpha) && alpha >= 0.0)
    m_undo->push(new SetAlpha(this, m_project.alpha, alpha));
}

void Document::setMode(JpcMode mode) {
  if (mode != m_project.mode)
    m_undo->push(new SetMode(this, m_project.mode, mode));
}

bool Document::assignMotion(int motion, int character, QString* out_error) {
  const auto fail = [&](const QString& text) {
    if (out_error)
      *out_error = text;
    return false;
  };
  if (motion < 0 || motion >= assetCount() || character < 0 || character >= assetCount() || motion == character)
    return fail(tr("choose a motion and a different character"));
  const Asset* source = m_assets[std::size_t(motion)].get();
  const Asset* target = m_assets[std::size_t(character)].get();
  if (!source || !target)
    return fail(tr("an asset is missing; relink it first"));
  if (source->clips.empty())
    return fail(tr("%1 has no clip to play").arg(QFileInfo(assetFilePath(motion)).fileName()));
  ProjectMapping mapping;
  mapping.motion = motion;
  mapping.character = character;
  mapping.mapping = MotionMapping::automatic(source->skeleton, target->skeleton);
  mapping.mapping.motionName = QFileInfo(assetFilePath(motion)).fileName().toStdString();
  mapping.mapping.characterName = QFileInfo(assetFilePath(character)).fileName().toStdString();
  if (mapping.mapping.pairs.empty())
    return fail(tr("no joint of %1 matches one of %2").arg(QString::fromStdString(mapping.mapping.motionName),
                                                            QString::fromStdString(mapping.mapping.characterName)));
  std::vector<ProjectMapping> after;
  for (const ProjectMapping& existing : m_project.mappings)
    if (existing.motion != motion || existing.character != character)
      after.push_back(existing);
  const QString text = tr("Assign %1 to %2 (%3 joint pairs)")
                           .arg(QString::fromStdString(mapping.mapping.motionName),
                                QString::fromStdString(mapping.mapping.characterName))
                           .arg(mapping.mapping.pairs.size());
  after.push_back(std::move(mapping));
  m_undo->push(new SetMappings(this, m_project.mappings, std::move(after), text));
  return true;
}

void Document::unassignMotion(int mapping) {
  if (mapping < 0 || mapping >= static_cast<int>(m_project.mappings.size()))
    return;
  std::vector<ProjectMapping> after = m_project.mappings;
  after.erase(after.begin() + mapping);
  m_undo->push(new SetMappings(this, m_project.mappings, std::move(after), tr("Unassign motion")));
}

bool Document::setMappingPair(int mapping, const QString& characterJoint, const QString& motionJoint) {
  if (mapping < 0 || mapping >= static_cast<int>(m_project.mappings.size()))
    return false;
  const ProjectMapping& entry = m_project.mappings[std::size_t(mapping)];
  const Asset* motion = entry.motion < assetCount() ? m_assets[std::size_t(entry.motion)].get() : nullptr;
  const Asset* character = entry.character < assetCount() ? m_assets[std::size_t(entry.character)].get() : nullptr;
  const std::string characterName = characterJoint.toStdString(), motionName = motionJoint.toStdString();
  if (!motion || !character || character->skeleton.find(characterName) < 0 ||
      (!motionName.empty() && motion->skeleton.find(motionName) < 0))
    return false;
  std::vector<ProjectMapping> after = m_project.mappings;
  MotionMapping& table = after[std::size_t(mapping)].mapping;
  if (motionName.empty())
    table.clear(characterName);
  else
    table.set(characterName, motionName);
  if (after == m_project.mappings)
    return false;
  const QString text = motionName.empty() ? tr("Unmap %1").arg(characterJoint)
                                          : tr("Map %1 to %2").arg(motionJoint, characterJoint);
  m_undo->push(new SetMappings(this, m_project.mappings, std::move(after), text));
  return true;
}

void Document::resetMapping(int mapping) {
  if (mapping < 0 || mapping >= static_cast<int>(m_project.mappings.size()))
    return;
  const ProjectMapping& entry = m_project.mappings[std::size_t(mapping)];
  const Asset* motion = entry.motion < assetCount() ? m_assets[std::size_t(entry.motion)].get() : nullptr;
  const Asset* character = entry.character < assetCount() ? m_assets[std::size_t(entry.character)].get() : nullptr;
  if (!motion || !character)
    return;
  std::vector<ProjectMapping> after = m_project.mappings;
  MotionMapping automatic = MotionMapping::automatic(motion->skeleton, character->skeleton);
  automatic.motionName = entry.mapping.motionName;
  automatic.characterName = entry.mapping.characterName;
  after[std::size_t(mapping)].mapping = std::move(automatic);
  if (after == m_project.mappings)
    return;
  m_undo->push(new SetMappings(this, m_project.mappings, std::move(after), tr("Automatic joint mapping")));
}

namespace {
// Drops entries that say nothing (all defaults) so projects stay small and compare equal.
void tidy(std::map<std::string, JointSettings>& joints) {
  for (auto it = joints.begin(); it != joints.end();) {
    auto& t = it->second.thresholds;
    while (!t.empty() && !t.back())
      t.pop_back();
    if (!it->second.alpha && t.empty() && !it->second.locked && it->second.meshImportance == 1.0)
      it = joints.erase(it);
    else
      ++it;
  }
}
} // namespace

void Document::setJointAlpha(const std::vector<int>& joints, std::optional<double> alpha) {
  if (currentAsset() < 0 || joints.empty())
    return;
  auto after = jointSettings(currentAsset());
  for (int joint : joints)
    after[jointName(joint)].alpha = alpha;
  tidy(after);
  if (after == jointSettings(currentAsset()))
    return;
  const QString text = joints.size() == 1 ? tr("Set alpha of %1").arg(QString::fromStdString(jointName(joints[0])))
                                          : tr("Set alpha of %1 joints").arg(joints.size());
  m_undo->push(new SetJointSettings(this, currentAsset(), jointSettings(currentAsset()), std::move(after), text,
                                    kCommandSetJointAlpha, joints));
}

void Document::setJointThreshold(const std::vector<int>& joints, int level, std::optional<double> threshold) {
  if (currentAsset() < 0 || joints.empty() || level <= 0 || level >= m_project.levelCount())
    return; // level 0 is the original: nothing to override
  auto after = jointSettings(currentAsset());
  for (int joint : joints) {
    auto& t = after[jointName(joint)].thresholds;
    if (static_cast<int>(t.size()) <= level)
      t.resize(static_cast<std::size_t>(level) + 1);
    t[static_cast<std::size_t>(level)] = threshold;
  }
  tidy(after);
  if (after == jointSettings(currentAsset()))
    return;
  std::vector<int> key = joints;
  key.push_back(-1 - level);
  const QString text = joints.size() == 1
                           ? tr("Set threshold of %1 at level %2").arg(QString::fromStdString(jointName(joints[0]))).arg(level)
                           : tr("Set threshold of %1 joints at level %2").arg(joints.size()).arg(level);
  m_undo->push(new SetJointSettings(this, currentAsset(), jointSettings(currentAsset()), std::move(after), text,
                                    kCommandSetJointThreshold, std::move(key)));
}

void Document::setJointsLocked(const std::vector<int>& joints, bool locked) {
  if (currentAsset() < 0 || joints.empty())
    return;
  auto after = jointSettings(currentAsset());
  for (int joint : joints)
    after[jointName(joint)].locked = locked;
  tidy(after);
  if (after == jointSettings(currentAsset()))
    return;
  const QString what = joints.size() == 1 ? QString::fromStdString(jointName(joints[0])) : tr("%1 joints").arg(joints.size());
  m_undo->push(new SetJointSettings(this, currentAsset(), jointSettings(currentAsset()), std::move(after),
                                    locked ? tr("Lock %1").arg(what) : tr("Unlock %1").arg(what)));
}

void Document::setJointMeshImportance(const std::vector<int>& joints, double importance) {
  if (currentAsset() < 0 || joints.empty() || !std::isfinite(importance) || !(importance > 0.0))
    return;
  auto after = jointSettings(currentAsset());
  for (int joint : joints)
    after[jointName(joint)].meshImportance = importance;
  tidy(after);
  if (after == jointSettings(currentAsset()))
    return;
  const QString text = joints.size() == 1
                           ? tr("Set mesh importance of %1").arg(QString::fromStdString(jointName(joints[0])))
                           : tr("Set mesh importance of %1 joints").arg(joints.size());
  m_undo->push(new SetJointSettings(this, currentAsset(), jointSettings(currentAsset()), std::move(after), text,
                                    kCommandSetJointMeshImportance, joints));
}

void Document::applyToChildren(int joint) {
  const Asset* a = currentAssetPtr();
  if (!a || joint < 0 || joint >= a->skeleton.jointCount())
    return;
  auto after = jointSettings(currentAsset());
  const auto found = after.find(jointName(joint));
  const JointSettings source = found != after.end() ? found->second : JointSettings{};
  std::vector<int> stack = a->skeleton.children(joint);
  while (!stack.empty()) {
    const int child = stack.back();
    stack.pop_back();
    after[jointName(child)] = source;
    for (int grandChild : a->skeleton.children(child))
      stack.push_back(grandChild);
  }
  tidy(after);
  if (after == jointSettings(currentAsset()))
    return;
  m_undo->push(new SetJointSettings(this, currentAsset(), jointSettings(currentAsset()), std::move(after),
                                    tr("Apply %1's settings to its children").arg(QString::fromStdString(jointName(joint)))));
}

namespace {
SetLevels::State levelState(const Project& project) {
  SetLevels::State state;
  state.lods = project.lods;
  for (const ProjectAsset& asset : project.assets)
    state.joints.push_back(asset.joints);
  return state;
}
SetLevels::State remapped(const Project& project, const std::vector<int>& order, const std::vector<LodLevel>& levels) {
  Project copy = project;
  remapLevels(copy, order, levels);
  return levelState(copy);
}
std::vector<int> identity(int count) {
  std::vector<int> order(static_cast<std::size_t>(count));
  std::iota(order.begin(), order.end(), 0);
  return order;
}
bool refuse(QString* out_error, const QString& reason) {
  if (out_error)
    *out_error = reason;
  return false;
}
} // namespace

void Document::addLevel(double threshold) {
  if (!std::isfinite(threshold) || threshold < 0.0)
    return;
  std::vector<LodLevel> levels = m_project.lods.levels;
  std::vector<int> order = identity(static_cast<int>(levels.size()));
  LodLevel level;
  int n = static_cast<int>(levels.size());
  auto taken = [&](const std::string& name) {
    return std::any_of(levels.begin(), levels.end(), [&](const LodLevel& l) { return l.name == name; });
  };
  while (taken("LOD" + std::to_string(n)))
    ++n;
  level.name = "LOD" + std::to_string(n);
  level.motionThreshold = threshold;
  level.meshRatio = levels.back().meshRatio;
  level.switchDistanceCm = levels.back().switchDistanceCm;
  levels.push_back(level);
  order.push_back(-1);
  m_undo->push(new SetLevels(this, levelState(m_project), remapped(m_project, order, levels),
                             tr("Add level %1 (E = %2)").arg(QString::fromStdString(level.name)).arg(threshold)));
}

void Document::removeLevel(int level) {
  const int count = m_project.levelCount();
  if (count <= 1 || level <= 0 || level >= count)
    return; // the original stays
  std::vector<int> order;
  std::vector<LodLevel> levels;
  for (int i = 0; i < count; ++i)
    if (i != level) {
      order.push_back(i);
      levels.push_back(m_project.lods.levels[static_cast<std::size_t>(i)]);
    }
  m_undo->push(new SetLevels(this, levelState(m_project), remapped(m_project, order, levels),
                             tr("Remove level %1").arg(QString::fromStdString(m_project.lods.levels[std::size_t(level)].name))));
}

void Document::moveLevel(int from, int to) {
  const int count = m_project.levelCount();
  if (from <= 0 || from >= count || to <= 0 || to >= count || from == to)
    return; // the original stays first
  std::vector<int> order = identity(count);
  const int moved = order[static_cast<std::size_t>(from)];
  order.erase(order.begin() + from);
  order.insert(order.begin() + to, moved);
  std::vector<LodLevel> levels;
  for (int i : order)
    levels.push_back(m_project.lods.levels[static_cast<std::size_t>(i)]);
  for (int i = 0; i < count; ++i) // distances stay with the positions, so they stay in order
    levels[std::size_t(i)].switchDistanceCm = m_project.lods.levels[std::size_t(i)].switchDistanceCm;
  m_undo->push(new SetLevels(this, levelState(m_project), remapped(m_project, order, levels),
                             tr("Move level %1 to position %2")
                                 .arg(QString::fromStdString(m_project.lods.levels[std::size_t(from)].name))
                                 .arg(to)));
}

void Document::setLevelThreshold(int level, double threshold) {
  const int count = m_project.levelCount();
  if (level <= 0 || level >= count || !std::isfinite(threshold) || threshold < 0.0 ||
      m_project.lods.levels[static_cast<std::size_t>(level)].motionThreshold == threshold)
    return;
  SetLevels::State after = levelState(m_project);
  after.lods.levels[static_cast<std::size_t>(level)].motionThreshold = threshold;
  m_undo->push(new SetLevels(this, levelState(m_project), std::move(after),
                             tr("Set level %1 threshold to %2").arg(level).arg(threshold), kCommandSetLevelThreshold,
                             level));
}

bool Document::renameLevel(int level, const QString& name, QString* out_error) {
  if (level < 0 || level >= m_project.levelCount())
    return refuse(out_error, tr("no level %1").arg(level));
  const std::string text = name.trimmed().toStdString();
  if (text.empty())
    return refuse(out_error, tr("a level needs a name"));
  for (int i = 0; i < m_project.levelCount(); ++i)
    if (i != level && m_project.lods.levels[std::size_t(i)].name == text)
      return refuse(out_error, tr("level %1 is already named '%2'").arg(i).arg(name.trimmed()));
  if (m_project.lods.levels[std::size_t(level)].name == text)
    return true;
  SetLevels::State after = levelState(m_project);
  after.lods.levels[static_cast<std::size_t>(level)].name = text;
  m_undo->push(new SetLevels(this, levelState(m_project), std::move(after),
                             tr("Rename level %1 to %2").arg(level).arg(name.trimmed())));
  return true;
}

bool Document::setLevelMeshRatio(int level, double ratio, QString* out_error) {
  if (level < 0 || level >= m_project.levelCount())
    return refuse(out_error, tr("no level %1").arg(level));
  if (level == 0)
    return refuse(out_error, tr("level 0 is the original: its mesh ratio is 1"));
  if (!(ratio > 0.0 && ratio <= 1.0))
    return refuse(out_error, tr("a mesh ratio is in (0, 1]"));
  if (m_project.lods.levels[std::size_t(level)].meshRatio == ratio)
    return true;
  SetLevels::State after = levelState(m_project);
  after.lods.levels[static_cast<std::size_t>(level)].meshRatio = ratio;
  m_undo->push(new SetLevels(this, levelState(m_project), std::move(after),
                             tr("Set level %1 mesh ratio to %2").arg(level).arg(ratio), kCommandSetLevelMeshRatio, level));
  return true;
}

bool Document::setLevelSwitchDistance(int level, double cm, QString* out_error) {
  const int count = m_project.levelCount();
  if (level < 0 || level >= count)
    return refuse(out_error, tr("no level %1").arg(level));
  if (level == 0)
    return refuse(out_error, tr("level 0 is the original: it is used from distance 0"));
  const auto& levels = m_project.lods.levels;
  const double low = levels[std::size_t(level - 1)].switchDistanceCm;
  if (!std::isfinite(cm) || cm < low)
    return refuse(out_error, tr("level %1's switch distance must be finite and at least the previous level's (%2 cm)")
                                 .arg(level)
                                 .arg(low));
  if (levels[std::size_t(level)].switchDistanceCm == cm)
    return true;
  SetLevels::State after = levelState(m_project);
  for (int i = level; i < count; ++i) // later levels nearer than this one move out with it
    if (i == level || after.lods.levels[std::size_t(i)].switchDistanceCm < cm)
      after.lods.levels[std::size_t(i)].switchDistanceCm = cm;
  m_undo->push(new SetLevels(this, levelState(m_project), std::move(after),
                             tr("Set level %1 switch distance to %2 cm").arg(level).arg(cm),
                             kCommandSetLevelSwitchDistance, level));
  return true;
}

bool Document::generateLevels(double pixels, int levels, QString* out_error) {
  const Asset* a = currentAssetPtr();
  if (!a)
    return refuse(out_error, tr("no asset in view"));
  if (m_levelsWatcher.isRunning())
    return refuse(out_error, tr("the previous generation is still running"));
  if (!(pixels > 0.0) || !std::isfinite(pixels) || levels < 1)
    return refuse(out_error, tr("a budget is > 0 pixels and at least one level"));
  LodBudgetOptions options;
  options.jpc = m_project.jpcSettings(currentAsset(), a->unitScale);
  options.projection = m_project.lods.projection;
  m_levelsCancel = std::make_shared<std::atomic<bool>>(false);
  m_levelsRunning = true;
  m_levelsText = tr("Generate %1 levels within %2 px").arg(levels).arg(pixels);
  emit levelGenerationStarted();
  // Motions assigned to this character play on it too: every level must hold for them.
  std::vector<std::pair<std::shared_ptr<const Asset>, MotionMapping>> motions;
  for (const ProjectMapping& mapping : m_project.mappings)
    if (mapping.character == currentAsset() && mapping.motion < assetCount() && m_assets[std::size_t(mapping.motion)])
      motions.emplace_back(m_assets[std::size_t(mapping.motion)], mapping.mapping);
  m_levelsWatcher.setFuture(QtConcurrent::run([asset = m_assets[std::size_t(currentAsset())], options, pixels, levels,
                                               motions, cancel = m_levelsCancel, hook = m_hook]() mutable {
    if (hook)
      hook(*cancel);
    if (cancel->load())
      return std::shared_ptr<Result<LodSet>>();
    std::vector<Clip> clips;
    for (const auto& [motion, mapping] : motions) {
      Result<RestPoseDifferences> differences = restPoseDifferences(mapping, motion->skeleton, asset->skeleton);
      if (!differences)
        return std::make_shared<Result<LodSet>>(Error("mapping of " + mapping.motionName + ": " + differences.message()));
      for (const Clip& clip : motion->clips) {
        Result<Clip> retargeted = retargetClip(*differences, motion->skeleton, clip, asset->skeleton);
        if (!retargeted)
          return std::make_shared<Result<LodSet>>(Error(mapping.motionName + ": " + retargeted.message()));
        clips.push_back(std::move(retargeted).value());
      }
    }
    options.clips = clips;
    return std::make_shared<Result<LodSet>>(LodSet::fromPixelBudget(*asset, pixels, levels, options));
  }));
  return true;
}

void Document::cancelLevelGeneration() {
  if (!m_levelsRunning)
    return;
  m_levelsCancel->store(true);
  m_levelsRunning = false;
  emit message(tr("Level generation cancelled; the levels are as they were"));
  emit levelGenerationFinished(false, tr("cancelled"));
}

void Document::onLevelsGenerated() {
  const std::shared_ptr<Result<LodSet>> result = m_levelsWatcher.result();
  if (!m_levelsRunning || (m_levelsCancel && m_levelsCancel->load()))
    return; // cancelled: already reported, the result is dropped
  m_levelsRunning = false;
  if (!result || !*result) {
    const QString reason = result ? QString::fromStdString(result->message()) : tr("no result");
    emit message(tr("warning: level generation: %1").arg(reason));
    emit levelGenerationFinished(false, reason);
    return;
  }
  const LodSet& generated = result->value();
  std::vector<int> order(generated.levels.size());
  for (std::size_t i = 0; i < order.size(); ++i)
    order[i] = i < m_project.lods.levels.size() ? static_cast<int>(i) : -1;
  Project copy = m_project;
  remapLevels(copy, order, generated.levels);
  copy.lods = generated;
  SetLevels::State after = levelState(copy);
  m_undo->push(new SetLevels(this, levelState(m_project), std::move(after), m_levelsText));
  emit message(m_levelsText);
  emit levelGenerationFinished(true, m_levelsText);
}

void Document::setAssetUnitScale(int index, double cmPerUnit) {
  if (index < 0 || index >= assetCount() || !m_assets[std::size_t(index)] || m_reimport->isRunning() ||
      !std::isfinite(cmPerUnit) || cmPerUnit < 0.0)
    return;
  m_reimportIndex = index;
  m_reimportScale = cmPerUnit;
  ImportOptions options;
  options.unitScale = cmPerUnit;
  m_reimport->start(assetFilePath(index), options);
}

// ---- setters for commands -----------------------------------------------------------

std::map<std::string, JointSettings> Document::jointSettings(int asset) const {
  return m_project.assets[static_cast<std::size_t>(asset)].joints;
}

void Document::setProjectAlpha(double alpha) {
  m_project.alpha = alpha;
  emit settingsChanged();
  requestAnalysis(true);
}

void Document::setProjectMode(JpcMode mode) {
  m_project.mode = mode;
  emit settingsChanged();
  requestAnalysis(true);
}

void Document::setJointSettings(int asset, const std::map<std::string, JointSettings>& joints) {
  m_project.assets[static_cast<std::size_t>(asset)].joints = joints;
  emit settingsChanged();
  if (asset == currentAsset())
    requestAnalysis(true);
}

void Document::setLevels(const LodSet& lods, const std::vector<std::map<std::string, JointSettings>>& joints) {
  m_project.lods = lods;
  for (std::size_t a = 0; a < joints.size() && a < m_project.assets.size(); ++a)
    m_project.assets[a].joints = joints[a];
  m_project.view.level = std::clamp(m_project.view.level, 0, static_cast<int>(lods.levels.size()) - 1);
  emit settingsChanged();
  emit currentChanged();
  requestAnalysis(true);
}

void Document::setMappings(const std::vector<ProjectMapping>& mappings) {
  m_project.mappings = mappings;
  emit mappingsChanged();
  emit assetsChanged(); // the Assets dock shows what drives what
}

void Document::insertAsset(int index, const ProjectAsset& entry, std::shared_ptr<const Asset> asset) {
  insertProjectAsset(m_project, index, entry);
  m_assets.insert(m_assets.begin() + index, std::move(asset));
  emit assetsChanged();
  if (currentAsset() >= index)
    ++m_project.view.asset;
  if (currentAsset() < 0 || !currentAssetPtr() || currentAssetPtr()->clips.empty())
    setCurrentAsset(index, 0);
}

void Document::replaceAsset(int index, const ProjectAsset& entry, std::shared_ptr<const Asset> asset) {
  m_project.assets[std::size_t(index)] = entry;
  m_assets[std::size_t(index)] = std::move(asset);
  emit assetsChanged();
  if (index == currentAsset()) {
    m_analysis.reset(); // other lengths: every figure changes
    requestAnalysis(true);
    emit currentChanged();
  }
}

void Document::eraseAsset(int index) {
  eraseProjectAsset(m_project, index);
  m_assets.erase(m_assets.begin() + index);
  emit assetsChanged();
  if (currentAsset() == index)
    setCurrentAsset(assetCount() > 0 ? 0 : -1, 0);
  else if (currentAsset() > index)
    --m_project.view.asset;
}

// ---- analysis -----------------------------------------------------------------------

void Document::requestAnalysis(bool fromEdit) {
  m_requestedAt = QDateTime::currentMSecsSinceEpoch();
  if (m_running) {
    m_pending = true;
    m_pendingFromEdit = m_pendingFromEdit || fromEdit;
    return;
  }
  m_pendingFromEdit = fromEdit;
  startAnalysis();
}

void Document::startAnalysis() {
  m_pending = false;
  const Asset* a = currentAssetPtr();
  if (!a || currentClip() < 0 || currentClip() >= static_cast<int>(a->clips.size())) {
    m_analysis.reset();
    emit analysisFinished(false, tr("no clip in view"));
    return;
  }
  AnalysisRequest request;
  request.asset = m_assets[static_cast<std::size_t>(currentAsset())];
  request.clip = currentClip();
  request.settings = m_project.jpcSettings(currentAsset(), a->unitScale);
  request.levelThresholds = m_project.levelThresholds();
  if (m_analysis && m_analysis->asset == request.asset && m_analysis->clip == request.clip &&
      m_analysis->levelThresholds == request.levelThresholds && m_analysis->settings.alpha == request.settings.alpha &&
      m_analysis->settings.mode == request.settings.mode && m_analysis->settings.joints == request.settings.joints) {
    emit analysisFinished(true, tr("figures unchanged"));
    return;
  }
  m_running = true;
  m_jobFromEdit = m_pendingFromEdit;
  m_pendingFromEdit = false;
  m_cancel = std::make_shared<std::atomic<bool>>(false);
  m_jobError = std::make_shared<std::string>();
  emit analysisStarted();
  QPointer<Document> self(this);
  auto progress = [self](int done, int total) {
    QMetaObject::invokeMethod(
        self.data(), [self, done, total] {
          if (self)
            emit self->analysisProgress(done, total);
        },
        Qt::QueuedConnection);
  };
  m_watcher.setFuture(QtConcurrent::run([request, previous = m_analysis, cancel = m_cancel, error = m_jobError,
                                         hook = m_hook, progress]() {
    if (hook)
      hook(*cancel);
    return buildAnalysis(request, previous, *cancel, progress, *error);
  }));
}

void Document::onAnalysisDone() {
  m_running = false;
  std::shared_ptr<const Analysis> result = m_watcher.result();
  const bool cancelled = m_cancel && m_cancel->load();
  const bool ok = result != nullptr;
  if (ok && !cancelled) {
    m_analysis = std::move(result);
    m_lastMs = static_cast<double>(QDateTime::currentMSecsSinceEpoch() - m_requestedAt);
  }
  if (m_pending && !cancelled) {
    startAnalysis();
    return;
  }
  if (cancelled) {
    // The edit whose figures were being computed is taken back: the document is as before.
    m_pending = false;
    // The command is complete on the stack by now (push() runs redo() before adding it).
    // Undo it, then drop it from the redo side: pushing a command truncates the redo tail,
    // and an obsolete one is deleted instead of added.
    if (m_jobFromEdit && m_undo->canUndo()) {
      m_undo->undo();
      auto* drop = new QUndoCommand;
      drop->setObsolete(true);
      m_undo->push(drop);
    }
    m_jobFromEdit = false;
    emit message(tr("Clustering cancelled; the last edit was taken back"));
    emit analysisFinished(false, tr("cancelled"));
    return;
  }
  m_jobFromEdit = false;
  if (!ok) {
    emit message(tr("warning: clustering failed: %1").arg(QString::fromStdString(*m_jobError)));
    emit analysisFinished(false, QString::fromStdString(*m_jobError));
    return;
  }
  emit analysisFinished(true, tr("%1 joint clusterings in %2 ms").arg(m_analysis->clusteredPairs).arg(m_lastMs));
}

void Document::cancelAnalysis() {
  if (m_running && m_cancel)
    m_cancel->store(true);
}

// ---- files --------------------------------------------------------------------------

namespace {
bool writeAtomically(const QString& path, const std::string& text, QString* out_error) {
  QSaveFile file(path);
  if (!file.open(QIODevice::WriteOnly)) {
    if (out_error)
      *out_error = file.errorString();
    return false;
  }
  file.write(text.data(), static_cast<qint64>(text.size()));
  if (!file.commit()) {
    if (out_error)
      *out_error = file.errorString();
    return false;
  }
  return true;
}
} // namespace

bool Document::save(const QString& path, QString* out_error) {
  Project copy = m_project;
  const std::string target = QFileInfo(path).absoluteFilePath().toStdString();
  for (int i = 0; i < assetCount(); ++i)
    copy.assets[static_cast<std::size_t>(i)].path = storedAssetPath(target, assetFilePath(i).toStdString());
  if (!writeAtomically(path, projectToJson(copy), out_error))
    return false;
  m_project = std::move(copy);
  m_fileName = QFileInfo(path).absoluteFilePath();
  m_undo->setClean();
  return true;
}

bool Document::saveRecovery(const QString& path, QString* out_error) const {
  Project copy = m_project;
  const std::string target = QFileInfo(path).absoluteFilePath().toStdString();
  for (int i = 0; i < assetCount(); ++i) // absolute: the recovery file lives elsewhere
    copy.assets[static_cast<std::size_t>(i)].path = QFileInfo(assetFilePath(i)).absoluteFilePath().toStdString();
  (void)target;
  return writeAtomically(path, projectToJson(copy), out_error);
}

bool Document::open(const QString& path, QString* out_error) {
  Result<Project> loaded = loadProjectFile(QFileInfo(path).absoluteFilePath().toStdString());
  if (!loaded) {
    if (out_error)
      *out_error = QString::fromStdString(loaded.message());
    return false;
  }
  cancelAnalysis();
  m_watcher.waitForFinished();
  m_running = false;
  m_undo->clear();
  m_project = std::move(loaded).value();
  m_fileName = QFileInfo(path).absoluteFilePath();
  m_assets.assign(m_project.assets.size(), nullptr);
  m_analysis.reset();
  m_currentJoint = -1;
  m_openMessage.clear();
  m_toLoad.clear();
  for (int i = 0; i < assetCount(); ++i)
    m_toLoad.push_back(i);
  emit assetsChanged();
  emit settingsChanged();
  emit currentChanged();
  importNextMissing();
  return true;
}

bool Document::recover(const QString& path, QString* out_error) {
  if (!open(path, out_error))
    return false;
  m_fileName.clear(); // the recovery file is no home for the project: Save asks where
  m_undo->resetClean();
  return true;
}

bool Document::isLoading() const { return !m_toLoad.empty() || m_loader->isRunning(); }

void Document::relinkAsset(int index, const QString& path) {
  if (index < 0 || index >= assetCount() || m_loader->isRunning())
    return;
  // Relinking changes where the file is, not what the project figures are: no undo step.
  m_project.assets[static_cast<std::size_t>(index)].path =
      m_fileName.isEmpty() ? QFileInfo(path).absoluteFilePath().toStdString()
                           : storedAssetPath(m_fileName.toStdString(), QFileInfo(path).absoluteFilePath().toStdString());
  m_toLoad = {index};
  m_openMessage.clear();
  importNextMissing();
}

void Document::importNextMissing() {
  if (m_loader->isRunning())
    return;
  if (m_toLoad.empty()) {
    if (m_project.view.joint.size() && currentAssetPtr()) {
      m_currentJoint = currentAssetPtr()->skeleton.find(m_project.view.joint);
      emit currentChanged();
    }
    emit projectOpened(m_openMessage.isEmpty(), m_openMessage.trimmed());
    return;
  }
  const int index = m_toLoad.front();
  ImportOptions options;
  options.unitScale = m_project.assets[static_cast<std::size_t>(index)].unitScale;
  m_loader->start(assetFilePath(index), options);
}

} // namespace mlod
