#pragma once
// The open project: the core Project, the imported assets it names, the undo stack every
// edit goes through, what is in view (asset, clip, level, joint) and the JPC figures of
// the clip in view (re-clustered off the UI thread after each edit, only where the edit
// reached). Views read it and call its intents; commands (commands.h) call its setters.

#include "core/asset.h"
#include "core/project.h"
#include "editor/document/analysis.h"

#include <QFutureWatcher>
#include <QObject>
#include <QString>
#include <QUndoStack>

#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

namespace mlod {

class ImportJob;

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
  QString assetFilePath(int index) const; // absolute

  // What is in view. The current joint is a skeleton index of the current asset, or -1.
  int currentAsset() const { return m_project.view.asset; }
  int currentClip() const { return m_project.view.clip; }
  int currentLevel() const { return m_project.view.level; }
  int currentJoint() const { return m_currentJoint; }
  const Asset* currentAssetPtr() const;
  const Clip* currentClipPtr() const;
  void setCurrentAsset(int asset, int clip = 0);
  void setCurrentLevel(int level);
  void setCurrentJoint(int joint);

  // The figures of the clip in view; null before the first clustering lands.
  std::shared_ptr<const Analysis> analysis() const { return m_analysis; }
  bool isAnalysing() const { return m_running; }
  double lastAnalysisMilliseconds() const { return m_lastMs; } // edit to figures, ms
  void cancelAnalysis();
  // Test hook: runs on the worker before any clustering, with the cancel flag.
  void setWorkerHook(std::function<void(const std::atomic<bool>&)> hook) { m_hook = std::move(hook); }

  // Intents: each pushes one command (merged with the previous one for slider drags).
  void addAsset(std::shared_ptr<const Asset> asset, const QString& path, double unitScale);
  void removeAsset(int index);
  void setAlpha(double alpha);
  void setMode(JpcMode mode);
  // Assigns motion asset `motion` to character asset `character` with the automatic joint
  // mapping (replacing an earlier assignment of that motion to that character).
  // Errors: assets missing, without a clip (motion), or no joint that matches.
  bool assignMotion(int motion, int character, QString* out_error = nullptr);
  void unassignMotion(int mapping);
  // Joint-mapping table edits of project().mappings[mapping], one undo step each:
  // `motionJoint` drives `characterJoint` (MotionMapping::set: a pair that held either goes);
  // an empty `motionJoint` leaves the character joint at its rest pose. Returns false (and
  // pushes nothing) for an unknown mapping or joint, or when nothing changes.
  bool setMappingPair(int mapping, const QString& characterJoint, const QString& motionJoint);
  // The automatic (name-matched) table again.
  void resetMapping(int mapping);
  void setJointAlpha(const std::vector<int>& joints, std::optional<double> alpha);
  void setJointThreshold(const std::vector<int>& joints, int level, std::optional<double> threshold);
  void setJointsLocked(const std::vector<int>& joints, bool locked);
  // Mesh importance (finite, > 0; 1 = as any other joint): scales the mesh LOD's cost of
  // removing the vertices the joints influence (core/mesh/mesh_lod.h).
  void setJointMeshImportance(const std::vector<int>& joints, double importance);
  void applyToChildren(int joint); // copies the joint's settings to every descendant
  // LOD levels (the project's LodSet; level 0 is the original: it keeps threshold 0, ratio 1
  // and distance 0, can be renamed, never removed or moved). A new level goes last, named
  // "LOD<n>", with the last level's mesh ratio and switch distance. Switch distances belong
  // to the positions: moving a level keeps the distance column in order.
  void addLevel(double threshold);
  void removeLevel(int level);
  void moveLevel(int from, int to);
  void setLevelThreshold(int level, double threshold);  // cm·degrees, >= 0
  // Each returns false (with a reason) and pushes nothing when the value is refused.
  bool renameLevel(int level, const QString& name, QString* out_error = nullptr); // non-empty, unique
  bool setLevelMeshRatio(int level, double ratio, QString* out_error = nullptr);  // (0, 1]
  // cm, at least the previous level's; later levels nearer than `cm` move out to it (same step).
  bool setLevelSwitchDistance(int level, double cm, QString* out_error = nullptr);
  // Generates the LOD set from a pixel budget off the UI thread (LodSet::fromPixelBudget:
  // motion and mesh levels together, for the asset in view with the project's JPC settings,
  // `levels` levels within `pixels` on screen, holding for the motions assigned to it too,
  // retargeted); one undo step when it lands, per-joint
  // overrides kept by level index. Cancelling drops the result: the document stays as it was
  // (the core call has no cancel point, so the worker finishes in the background).
  // Returns false (with a reason) when no asset is in view or a generation still runs.
  bool generateLevels(double pixels, int levels, QString* out_error = nullptr);
  void cancelLevelGeneration();
  bool isGeneratingLevels() const { return m_levelsRunning; }
  bool isLevelWorkerBusy() const { return m_levelsWatcher.isRunning(); } // a cancelled one may still run
  // Imports the asset's file again at `cmPerUnit` (0 = the file's own) in the background,
  // then pushes one command; unitScaleChanged() follows either way.
  void setAssetUnitScale(int index, double cmPerUnit);

  // Files. save() writes atomically (QSaveFile); open() reads the project and imports
  // its assets in the background (projectOpened() follows). Errors leave the document as it was.
  bool save(const QString& path, QString* out_error = nullptr);
  bool open(const QString& path, QString* out_error = nullptr);
  bool saveRecovery(const QString& path, QString* out_error = nullptr) const; // the autosave copy
  // Opens a recovery file as an unsaved project (no file name, modified).
  bool recover(const QString& path, QString* out_error = nullptr);
  // Relinks a missing asset to `path` (imported in the background; assetsChanged() follows).
  void relinkAsset(int index, const QString& path);
  bool isLoading() const;

  // Setters for commands (no undo; they notify the views).
  void setProjectAlpha(double alpha);
  void setProjectMode(JpcMode mode);
  void setJointSettings(int asset, const std::map<std::string, JointSettings>& joints);
  void setLevels(const LodSet& lods, const std::vector<std::map<std::string, JointSettings>>& joints);
  void insertAsset(int index, const ProjectAsset& entry, std::shared_ptr<const Asset> asset);
  void eraseAsset(int index);
  void replaceAsset(int index, const ProjectAsset& entry, std::shared_ptr<const Asset> asset);
  void setMappings(const std::vector<ProjectMapping>& mappings);
  std::map<std::string, JointSettings> jointSettings(int asset) const;

signals:
  void assetsChanged();
  void settingsChanged();      // alpha, joint settings or levels
  void mappingsChanged();
  void currentChanged();       // asset, clip, level or joint in view
  void analysisStarted();
  void analysisProgress(int done, int total);
  void analysisFinished(bool ok, const QString& message); // ok = new figures in analysis()
  void projectOpened(bool ok, const QString& message);
  void unitScaleChanged(bool ok, const QString& message);
  void message(const QString& line); // for the log
  void levelGenerationStarted();
  void levelGenerationFinished(bool ok, const QString& message);

private:
  // `fromEdit`: an edit (a command's setter) asks; cancelling its job takes the edit back.
  void requestAnalysis(bool fromEdit = false);
  void startAnalysis();
  void onAnalysisDone();
  void importNextMissing();
  void onLevelsGenerated();
  std::string jointName(int joint) const;

  Project m_project;
  std::vector<std::shared_ptr<const Asset>> m_assets;
  QUndoStack* m_undo = nullptr;
  QString m_fileName;
  int m_currentJoint = -1;

  std::shared_ptr<const Analysis> m_analysis;
  QFutureWatcher<std::shared_ptr<const Analysis>> m_watcher;
  std::shared_ptr<std::atomic<bool>> m_cancel;
  std::shared_ptr<std::string> m_jobError;
  std::function<void(const std::atomic<bool>&)> m_hook;
  bool m_running = false;
  bool m_pending = false;
  bool m_jobFromEdit = false;     // the running job computes the figures of the last edit
  bool m_pendingFromEdit = false; // likewise for the request waiting behind it
  qint64 m_requestedAt = 0;
  double m_lastMs = 0.0;

  QFutureWatcher<std::shared_ptr<Result<LodSet>>> m_levelsWatcher;
  std::shared_ptr<std::atomic<bool>> m_levelsCancel;
  bool m_levelsRunning = false;
  QString m_levelsText; // the undo text of the running generation

  ImportJob* m_loader = nullptr;
  ImportJob* m_reimport = nullptr; // setAssetUnitScale()
  int m_reimportIndex = -1;
  double m_reimportScale = 0.0;
  std::vector<int> m_toLoad; // asset indices still to import after open()/relink
  QString m_openMessage;
};

} // namespace mlod
