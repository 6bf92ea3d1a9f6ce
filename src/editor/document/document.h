#pragma once
// The open project (docs/architecture.md section 7, Tiled's model): the state — the core
// Project, the imported assets it names, what is in view (asset, clip, level, joint) — and
// the undo stack every change goes through. Views read it; the edits of edits.h check their
// input with core's rules and push small commands (commands.h), which alone change the
// project through the private functions below.
//
// Work off the UI thread belongs to small runners the document owns: the analysis of the clip
// in view (AnalysisRunner, re-run after each change), level generation (LevelGenerator) and
// asset loading (AssetLoader: open, relink, a new unit scale).

#include "core/asset.h"
#include "core/project.h"
#include "editor/document/analysis_runner.h"

#include <QList>
#include <QObject>
#include <QString>
#include <QUndoStack>
#include <memory>
#include <optional>
#include <vector>

namespace mlod {

class AssetLoader;
class LevelGenerator;

class Document : public QObject {
  Q_OBJECT
public:
  explicit Document(QObject* parent = nullptr);
  ~Document() override;

  const Project& project() const { return m_project; }
  QUndoStack* undoStack() const { return m_undo; }
  QString fileName() const { return m_fileName; } // empty until saved or opened
  bool isModified() const { return !m_undo->isClean(); }

  // Assets, parallel to project().assets; null where the file is missing (relink it).
  int assetCount() const { return static_cast<int>(m_assets.size()); }
  std::shared_ptr<const Asset> asset(int index) const { return m_assets[static_cast<std::size_t>(index)]; }
  QString assetFilePath(int index) const;            // absolute
  std::string storedPath(const QString& file) const; // as the project stores a file's path
  std::vector<const Asset*> importedAssets() const;  // asset(i).get() for every i
  // Files imported for opening, relinking and unit changes so far: assets naming one file share
  // one import (AssetLoader).
  int importCount() const;

  // What is in view (not an edit: no undo). The current joint is a skeleton index of the
  // current asset, or -1.
  int currentAsset() const { return m_project.view.asset; }
  int currentClip() const { return m_project.view.clip; }
  int currentLevel() const { return m_project.view.level; }
  // The character the motion in view is viewed on (the viewport's character box), or -1 (on
  // its own skeleton, or an asset that is no mapped motion). Not an edit: no undo. Always one
  // the motion is mapped onto: setViewedCharacter() refuses others (-1), and it goes back to
  // -1 when the asset in view changes or its mapping goes.
  int viewedCharacter() const { return m_viewedCharacter; }
  void setViewedCharacter(int character);
  // The asset whose LOD set is in view (core/project.h's lodSetOwner(): the viewed character,
  // else the motion's first mapping's, else the asset itself; -1 with no asset in view), and
  // its file name: what the level docks, Budget, crowd and Export name.
  int lodSetOwnerInView() const { return lodSetOwner(m_project, currentAsset(), m_viewedCharacter); }
  QString lodSetOwnerName() const;
  // The LOD set of the asset in view (core/project.h's lodSetFor(): a character owns its
  // set; a motion plays with the set of the character it is viewed on), and its level
  // count: what the level docks show and the level edits change.
  const LodSet& lods() const { return lodSetFor(m_project, currentAsset(), m_viewedCharacter); }
  int levelCount() const { return static_cast<int>(lods().levels.size()); }
  int currentJoint() const { return m_currentJoint; }
  const Asset* currentAssetPtr() const;
  const Clip* currentClipPtr() const;
  void setCurrentAsset(int asset, int clip = 0);
  void setCurrentLevel(int level);
  void setCurrentJoint(int joint);

  // The runners. analysis() is the figures of the clip in view; null before the first land.
  AnalysisRunner* analysisRunner() const { return m_analysis; }
  LevelGenerator* levelGenerator() const { return m_generator; }
  std::shared_ptr<const JpcAnalysis> analysis() const { return m_analysis->snapshot(); }
  bool isAnalysing() const { return m_analysis->isRunning(); }
  bool isLoading() const;
  // A job the artist waits for runs (an export, the Budget preview, a level generation: they
  // say so): the views' own background builds (the viewport's level mesh, the crowd's
  // levels) wait until it ends, so that it has the cores (issue 26: the studio's export right
  // after opening a project shared two cores with both and took 1.6 s more than
  // `motionlod export`; the first Budget preview took 7.4-8.1 s there, 4.9-7.4 s without).
  bool isWaitedJobRunning() const { return m_waitedJobs > 0; }
  void beginWaitedJob();
  void endWaitedJob(); // once per beginWaitedJob()

  // Imports the asset's file again at `cmPerUnit` (0 = the file's own) in the background,
  // then pushes one command; unitScaleChanged() follows either way.
  void setAssetUnitScale(int index, double cmPerUnit);

  // Files. save() writes atomically (QSaveFile); open() reads the project and imports
  // its assets in the background (projectOpened() follows). Errors leave the document as it was.
  // `options` say where the project's assets may be (core/project.h).
  bool save(const QString& path, QString* out_error = nullptr);
  bool open(const QString& path, const ProjectFileOptions& options, QString* out_error = nullptr);
  // An empty, untitled project (File > New Project): no asset, the default settings, no undo history.
  void newProject();
  // The autosave copy at `path`, and beside it (recoveryOriginPath()) the project file it is
  // unsaved work of, if any.
  bool saveRecovery(const QString& path, QString* out_error = nullptr) const;
  // Opens a recovery file as unsaved work (modified) of the project file it was saved for, or
  // of an untitled project when it was saved for none.
  bool recover(const QString& path, QString* out_error = nullptr);
  static QString recoveryOriginPath(const QString& recoveryPath);
  // Relinks a missing asset to `path` (imported in the background; assetsChanged() follows).
  // Not an edit of the figures: no undo step.
  void relinkAsset(int index, const QString& path);

signals:
  // The asset list changed (added, removed, relinked, mappings); once after all of a
  // project's assets are imported.
  void assetsChanged();
  // One import of a list landed: the assets at `indices` (one file) are now imported; the
  // list is as it was. Views update those rows alone, so loading stays linear in the assets.
  void assetsLoaded(const QList<int>& indices);
  void settingsChanged(); // alpha, joint settings or levels
  void mappingsChanged();
  void currentChanged(); // asset, clip, level, joint or viewed character in view
  void analysisStarted();
  void analysisProgress(int done, int total);
  void analysisFinished(bool ok, const QString& message); // ok = new figures in analysis()
  void projectOpened(bool ok, const QString& message);
  void unitScaleChanged(bool ok, const QString& message);
  void message(const QString& line); // for the log
  void waitedJobChanged(bool running); // isWaitedJobRunning() changed

private:
  // What the commands apply (commands.h); nothing else changes the project's figures.
  friend class SetJointSettings;
  friend class SetLevels;
  friend class SetAlpha;
  friend class SetMode;
  friend class ChangeAssets;
  friend class SetMappings;
  friend class ReplaceAsset;
  void applyAlpha(double alpha);
  void applyMode(JpcMode mode);
  void applyJointSettings(int asset, const std::map<std::string, JointSettings>& joints);
  void applyLevels(const LodSet& lods, const std::vector<std::optional<LodSet>>& own,
                   const std::vector<std::map<std::string, JointSettings>>& joints);
  void insertAsset(int index, const ProjectAsset& entry, std::shared_ptr<const Asset> asset);
  void eraseAsset(int index);
  void replaceAsset(int index, const ProjectAsset& entry, std::shared_ptr<const Asset> asset);
  void applyMappings(const std::vector<ProjectMapping>& mappings);

  std::optional<JpcAnalysisRequest> analysisRequest() const;
  // After a change of the asset in view or of the mappings: the viewed character kept only
  // where the motion in view is still mapped onto it.
  void validateViewedCharacter();
  // After a change of what the set in view is: the level in view clamped to it, and, when
  // the set is another than `before`, the views told and the figures asked for again
  // (`fromEdit`: by an edit, which a cancelled clustering takes back).
  void followLodSet(const LodSet& before, bool fromEdit);
  std::string jointName(int joint) const;
  void takeBackLastEdit();
  void loadAssets(std::vector<int> indices);

  Project m_project;
  std::vector<std::shared_ptr<const Asset>> m_assets;
  QUndoStack* m_undo = nullptr;
  QString m_fileName;
  int m_currentJoint = -1;
  int m_viewedCharacter = -1; // viewedCharacter()
  int m_waitedJobs = 0; // waited-for jobs running
  AnalysisRunner* m_analysis = nullptr;
  LevelGenerator* m_generator = nullptr;
  AssetLoader* m_loader = nullptr;     // open, relink
  AssetLoader* m_reimporter = nullptr; // setAssetUnitScale()
};

} // namespace mlod
