#include "editor/document/document.h"

#include "editor/document/asset_loader.h"
#include "editor/document/commands.h"
#include "editor/document/level_generator.h"

#include <QFile>
#include <QFileInfo>
#include <QSaveFile>
#include <algorithm>
#include <cassert>
#include <cmath>

namespace mlod {

namespace {
bool refuse(QString* out_error, const QString& reason) {
  if (out_error)
    *out_error = reason;
  return false;
}

bool writeAtomically(const QString& path, const std::string& text, QString* out_error) {
  QSaveFile file(path);
  if (!file.open(QIODevice::WriteOnly))
    return refuse(out_error, file.errorString());
  file.write(text.data(), static_cast<qint64>(text.size()));
  return file.commit() || refuse(out_error, file.errorString());
}
} // namespace

Document::Document(QObject* parent)
    : QObject(parent), m_undo(new QUndoStack(this)),
      m_analysis(new AnalysisRunner([this] { return analysisRequest(); }, this)), m_generator(new LevelGenerator(this)),
      m_loader(new AssetLoader(this)), m_reimporter(new AssetLoader(this)) {
  connect(m_analysis, &AnalysisRunner::started, this, &Document::analysisStarted);
  connect(m_analysis, &AnalysisRunner::progress, this, &Document::analysisProgress);
  connect(m_analysis, &AnalysisRunner::finished, this, &Document::analysisFinished);
  connect(m_analysis, &AnalysisRunner::message, this, &Document::message);
  connect(m_analysis, &AnalysisRunner::editCancelled, this, &Document::takeBackLastEdit);

  connect(m_loader, &AssetLoader::loaded, this,
          [this](const std::vector<AssetLoader::Item>& items, std::shared_ptr<const Asset> asset) {
            QList<int> indices;
            for (const AssetLoader::Item& item : items) {
              m_assets[std::size_t(item.index)] = asset;
              indices << item.index;
            }
            emit message(items.size() == 1 ? tr("Loaded %1").arg(items.front().path)
                                           : tr("Loaded %1 (%2 assets)").arg(items.front().path).arg(items.size()));
            emit assetsLoaded(indices);
            const int shown = currentAsset() < 0 ? items.front().index : currentAsset();
            if (indices.contains(shown)) {
              m_project.view.asset = shown;
              m_analysis->request();
              emit currentChanged();
            }
          });
  connect(m_loader, &AssetLoader::failed, this,
          [this](const std::vector<AssetLoader::Item>& items, const QString& reason) {
            emit message(tr("warning: %1: %2 (relink it in the Assets dock)").arg(items.front().path, reason));
          });
  connect(m_loader, &AssetLoader::finished, this, [this](const QString& failures) {
    emit assetsChanged(); // once for the list: what depends on every asset (mappings, titles) follows
    if (!m_project.view.joint.empty() && currentAssetPtr()) {
      m_currentJoint = currentAssetPtr()->skeleton.find(m_project.view.joint);
      emit currentChanged();
    }
    emit projectOpened(failures.isEmpty(), failures);
  });

  connect(m_reimporter, &AssetLoader::loaded, this,
          [this](const std::vector<AssetLoader::Item>& items, std::shared_ptr<const Asset> asset) {
            const AssetLoader::Item& item = items.front(); // one asset at a time
            const int index = item.index;
            if (index >= assetCount() || assetFilePath(index) != item.path) {
              emit unitScaleChanged(false, tr("the asset changed while it was imported again"));
              return;
            }
            ProjectAsset after = m_project.assets[std::size_t(index)];
            after.unitScale = item.options.unitScale;
            m_undo->push(new ReplaceAsset(
                this, index, m_project.assets[std::size_t(index)], m_assets[std::size_t(index)], after, asset,
                tr("Set unit of %1 to %2 cm").arg(QFileInfo(item.path).fileName()).arg(asset->unitScale)));
            emit unitScaleChanged(true, tr("%1: %2 cm per file unit").arg(item.path).arg(asset->unitScale));
          });
  connect(m_reimporter, &AssetLoader::failed, this,
          [this](const std::vector<AssetLoader::Item>& items, const QString& reason) {
            emit message(tr("warning: %1: %2").arg(items.front().path, reason));
            emit unitScaleChanged(false, reason);
          });
}

Document::~Document() = default;

QString Document::assetFilePath(int index) const {
  const std::string& stored = m_project.assets[static_cast<std::size_t>(index)].path;
  if (m_fileName.isEmpty())
    return QFileInfo(QString::fromStdString(stored)).absoluteFilePath();
  return QString::fromStdString(resolveAssetPath(m_fileName.toStdString(), stored).string());
}

std::string Document::storedPath(const QString& file) const {
  const std::string absolute = QFileInfo(file).absoluteFilePath().toStdString();
  return m_fileName.isEmpty() ? absolute : storedAssetPath(m_fileName.toStdString(), absolute);
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

int Document::importCount() const {
  return m_loader->importCount() + m_reimporter->importCount();
}

bool Document::isLoading() const {
  return m_loader->isLoading();
}

void Document::beginWaitedJob() {
  if (m_waitedJobs++ == 0)
    emit waitedJobChanged(true);
}

void Document::endWaitedJob() {
  assert(m_waitedJobs > 0);
  if (m_waitedJobs > 0 && --m_waitedJobs == 0)
    emit waitedJobChanged(false);
}

void Document::setCurrentAsset(int asset, int clip) {
  if (asset == currentAsset() && clip == currentClip())
    return;
  m_project.view.asset = asset;
  m_project.view.clip = clip;
  validateViewedCharacter(); // another motion may be mapped onto the same character: kept
  // each character has its own levels: the level in view is one of the new asset's
  m_project.view.level = std::clamp(m_project.view.level, 0, levelCount() - 1);
  m_currentJoint = -1;
  m_project.view.joint.clear();
  m_analysis->reset();
  m_analysis->request();
  emit currentChanged();
}

void Document::setViewedCharacter(int character) {
  if (!isMappedOnto(m_project, currentAsset(), character))
    character = -1;
  if (character == m_viewedCharacter)
    return;
  const LodSet before = lods();
  m_viewedCharacter = character;
  followLodSet(before, false);
  emit currentChanged();
}

QString Document::lodSetOwnerName() const {
  return QString::fromStdString(assetFileName(m_project, lodSetOwnerInView()));
}

void Document::validateViewedCharacter() {
  if (!isMappedOnto(m_project, currentAsset(), m_viewedCharacter))
    m_viewedCharacter = -1;
}

void Document::followLodSet(const LodSet& before, bool fromEdit) {
  m_project.view.level = std::clamp(m_project.view.level, 0, levelCount() - 1);
  if (lods() == before)
    return;
  // other levels, so other figures (a cancelled clustering takes back an edit, never a view change)
  emit settingsChanged();
  m_analysis->request(fromEdit);
}

void Document::setCurrentLevel(int level) {
  level = std::clamp(level, 0, levelCount() - 1);
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

std::optional<JpcAnalysisRequest> Document::analysisRequest() const {
  const Asset* a = currentAssetPtr();
  if (!a || currentClip() < 0 || currentClip() >= static_cast<int>(a->clips.size()))
    return std::nullopt;
  JpcAnalysisRequest request;
  request.asset = m_assets[static_cast<std::size_t>(currentAsset())];
  request.clip = currentClip();
  request.settings = m_project.jpcSettings(currentAsset(), a->unitScale);
  request.levelThresholds = levelThresholdsFor(m_project, currentAsset(), m_viewedCharacter);
  return request;
}

// The edit whose figures were being computed is taken back: the document is as before. The
// command is complete on the stack (push() runs redo() before adding it): undo it, then drop
// it from the redo side (pushing truncates the redo tail, and an obsolete command is deleted
// instead of added).
void Document::takeBackLastEdit() {
  if (!m_undo->canUndo())
    return;
  m_undo->undo();
  auto* drop = new QUndoCommand;
  drop->setObsolete(true);
  m_undo->push(drop);
}

std::vector<const Asset*> Document::importedAssets() const {
  std::vector<const Asset*> out;
  for (const auto& asset : m_assets)
    out.push_back(asset.get());
  return out;
}

void Document::setAssetUnitScale(int index, double cmPerUnit) {
  if (index < 0 || index >= assetCount() || !m_assets[std::size_t(index)] || m_reimporter->isLoading() ||
      !std::isfinite(cmPerUnit) || cmPerUnit < 0.0)
    return;
  ImportOptions options;
  options.unitScale = cmPerUnit;
  m_reimporter->load({{index, assetFilePath(index), options}});
}

// ---- what the commands apply ----------------------------------------------------------

void Document::applyAlpha(double alpha) {
  m_project.alpha = alpha;
  emit settingsChanged();
  m_analysis->request(true);
}

void Document::applyMode(JpcMode mode) {
  m_project.mode = mode;
  emit settingsChanged();
  m_analysis->request(true);
}

void Document::applyJointSettings(int asset, const std::map<std::string, JointSettings>& joints) {
  m_project.assets[static_cast<std::size_t>(asset)].joints = joints;
  emit settingsChanged();
  if (asset == currentAsset())
    m_analysis->request(true);
}

void Document::applyLevels(const LodSet& lods, const std::vector<std::optional<LodSet>>& own,
                           const std::vector<std::map<std::string, JointSettings>>& joints) {
  m_project.lods = lods;
  for (std::size_t a = 0; a < own.size() && a < m_project.assets.size(); ++a)
    m_project.assets[a].lods = own[a];
  for (std::size_t a = 0; a < joints.size() && a < m_project.assets.size(); ++a)
    m_project.assets[a].joints = joints[a];
  m_project.view.level = std::clamp(m_project.view.level, 0, levelCount() - 1);
  emit settingsChanged();
  emit currentChanged();
  m_analysis->request(true);
}

void Document::applyMappings(const std::vector<ProjectMapping>& mappings) {
  const LodSet before = lods();
  const int viewed = m_viewedCharacter;
  m_project.mappings = mappings;
  validateViewedCharacter(); // its mapping may be gone
  emit mappingsChanged();
  emit assetsChanged(); // the Assets dock shows what drives what
  if (lods() == before && viewed == m_viewedCharacter)
    return;
  // The motion in view now plays with another set (its character's, or its own again when
  // unassigned): other levels, so other figures.
  followLodSet(before, true);
  emit currentChanged();
}

void Document::insertAsset(int index, const ProjectAsset& entry, std::shared_ptr<const Asset> asset) {
  insertProjectAsset(m_project, index, entry);
  m_assets.insert(m_assets.begin() + index, std::move(asset));
  if (m_viewedCharacter >= index) // the mappings followed their assets (insertProjectAsset())
    ++m_viewedCharacter;
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
    m_analysis->reset(); // other lengths: every figure changes
    m_analysis->request(true);
    emit currentChanged();
  }
}

void Document::eraseAsset(int index) {
  eraseProjectAsset(m_project, index);
  m_assets.erase(m_assets.begin() + index);
  if (m_viewedCharacter > index) // the mappings followed their assets; one onto `index` went with it
    --m_viewedCharacter;
  else if (m_viewedCharacter == index)
    m_viewedCharacter = -1;
  emit assetsChanged();
  if (currentAsset() == index)
    setCurrentAsset(assetCount() > 0 ? 0 : -1, 0);
  else if (currentAsset() > index)
    --m_project.view.asset;
}

// ---- files --------------------------------------------------------------------------

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

QString Document::recoveryOriginPath(const QString& recoveryPath) { return recoveryPath + ".origin"; }

bool Document::saveRecovery(const QString& path, QString* out_error) const {
  Project copy = m_project;
  for (int i = 0; i < assetCount(); ++i) // absolute: the recovery file lives elsewhere
    copy.assets[static_cast<std::size_t>(i)].path = QFileInfo(assetFilePath(i)).absoluteFilePath().toStdString();
  // beside it, the project file it is unsaved work of (none: an untitled project)
  const QString origin = recoveryOriginPath(path);
  if (m_fileName.isEmpty())
    QFile::remove(origin);
  else if (!writeAtomically(origin, m_fileName.toStdString(), out_error))
    return false;
  return writeAtomically(path, projectToJson(copy), out_error);
}

bool Document::open(const QString& path, const ProjectFileOptions& options, QString* out_error) {
  Result<Project> loaded = loadProjectFile(QFileInfo(path).absoluteFilePath().toStdString(), options);
  if (!loaded)
    return refuse(out_error, QString::fromStdString(loaded.message()));
  m_analysis->stop();
  m_undo->clear();
  m_project = std::move(loaded).value();
  m_fileName = QFileInfo(path).absoluteFilePath();
  m_assets.assign(m_project.assets.size(), nullptr);
  m_analysis->reset();
  m_currentJoint = -1;
  m_viewedCharacter = -1;
  emit assetsChanged();
  emit settingsChanged();
  emit currentChanged();
  std::vector<int> all(m_project.assets.size());
  for (std::size_t i = 0; i < all.size(); ++i)
    all[i] = static_cast<int>(i);
  loadAssets(std::move(all));
  return true;
}

void Document::newProject() {
  m_analysis->stop();
  m_undo->clear();
  m_project = Project{};
  m_fileName.clear();
  m_assets.clear();
  m_analysis->reset();
  m_currentJoint = -1;
  m_viewedCharacter = -1;
  emit assetsChanged();
  emit settingsChanged();
  emit currentChanged();
}

bool Document::recover(const QString& path, QString* out_error) {
  // Its asset paths are absolute (saveRecovery()): the files the project had open.
  if (!open(path, {.allowOutsideAssets = true}, out_error))
    return false;
  // The recovery file is no home for the project: it is the project file it was saved for
  // (Save writes there, asset paths stored as that file stores them), or untitled (Save asks
  // where). Either way the recovered work is unsaved.
  m_fileName.clear();
  QFile origin(recoveryOriginPath(path));
  if (origin.open(QIODevice::ReadOnly)) {
    const QString project = QString::fromUtf8(origin.readAll()).trimmed();
    if (!project.isEmpty()) {
      std::vector<QString> files;
      for (int i = 0; i < assetCount(); ++i)
        files.push_back(assetFilePath(i));
      m_fileName = QFileInfo(project).absoluteFilePath();
      for (int i = 0; i < assetCount(); ++i)
        m_project.assets[static_cast<std::size_t>(i)].path = storedPath(files[static_cast<std::size_t>(i)]);
    }
  }
  m_undo->resetClean();
  return true;
}

void Document::relinkAsset(int index, const QString& path) {
  if (index < 0 || index >= assetCount() || m_loader->isLoading())
    return;
  m_project.assets[static_cast<std::size_t>(index)].path = storedPath(path);
  loadAssets({index});
}

void Document::loadAssets(std::vector<int> indices) {
  std::vector<AssetLoader::Item> items;
  for (int index : indices) {
    ImportOptions options;
    options.unitScale = m_project.assets[static_cast<std::size_t>(index)].unitScale;
    items.push_back({index, assetFilePath(index), options});
  }
  m_loader->load(std::move(items));
}

} // namespace mlod
