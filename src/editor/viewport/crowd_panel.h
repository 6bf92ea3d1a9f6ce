#pragma once
// The Crowd dock (docs/architecture.md section 7): N agents of the character in view (1 to 10,000) on
// a grid or scattered, each at its own time offset, each at the LOD level the runtime's
// selection gives it from the project's LOD set (distance or screen size, hysteresis), drawn
// instanced per level; a toggle tints agents by level; an overlay gives the agents per
// level, joints evaluated against full detail, vertices skinned, the CPU time of pose
// evaluation and the frame rate. The work is core's Crowd (core/crowd/crowd.h); the levels
// are built off the UI thread (cancelled when the inputs change again; held back while a job
// the artist waits for runs, Document::isWaitedJobRunning()). "Compare" runs the
// paper's Figure 12 on the crowd on screen (core's compareCrowdConfigurations(): the same
// agents, camera and clip time with no simplification, skeletal only, mesh only and both,
// pose evaluation plus CPU skinning) off the UI thread and shows what the LOD set buys, in ms
// per frame and x: the median and range of kCompareRepetitions repetitions (one sample on a
// busy machine said 2.4x, 2.6x and 7.9x for the same crowd). A comparison belongs to the
// character, clip, LOD set and settings it ran on: when any of them changes it is cleared
// (a running one is cancelled and its result dropped).

#include "core/asset.h"
#include "core/crowd/crowd.h"
#include "core/project.h"
#include "editor/viewport/scene_view.h"

#include <QElapsedTimer>
#include <QFutureWatcher>
#include <QTimer>
#include <QWidget>

#include <atomic>
#include <map>
#include <memory>

class QCheckBox;
class QComboBox;
class QDoubleSpinBox;
class QLabel;
class QSpinBox;

namespace mlod {

class Document;
class Playback;

// Tint of LOD level `level` (distinct hues: green, yellow, orange, red, magenta, blue ...).
glm::vec4 crowdLevelTint(int level);

class CrowdPanel : public QWidget {
  Q_OBJECT
public:
  CrowdPanel(Document* document, Playback* playback, QWidget* parent = nullptr);
  ~CrowdPanel() override;

  SceneView* sceneView() const { return m_view; } // null where the platform has no OpenGL
  QSpinBox* agentsBox() const { return m_agents; }
  QComboBox* layoutBox() const { return m_layout; }
  QComboBox* selectionBox() const { return m_selectionMode; }
  QCheckBox* tintBox() const { return m_tint; }
  const Crowd& crowd() const { return m_crowd; }
  bool isBuilding() const { return m_watcher.isRunning() || m_rebuildTimer.isActive(); }
  bool hasLevels() const { return m_crowd.levelCount() > 0; }
  QString lastError() const { return m_error; }
  QStringList overlayLines() const { return m_overlay; }
  double framesPerSecond() const { return m_fps; }

  void setAgentCount(int agents);
  // Plays the asset in view on the character of project().mappings[mapping] (-1: its own
  // skeleton), as the Viewport shows it.
  void setMapping(int mapping);
  int mapping() const { return m_mapping; }
  // Builds the levels now if the dock's inputs changed (the dock builds when shown).
  void requestLevels();
  // Poses the crowd at the playback time from the current camera and redraws.
  void refresh();
  // Renders `frames` frames as fast as they come, 1/60 s of clip time apart, then emits
  // measured() with the mean pose-evaluation CPU time (ms) and the frame rate.
  void measure(int frames);
  // The four-way comparison on the crowd on screen, `frames` frames from the playback time,
  // `repetitions` times after a warm-up (figures: medians and ranges); emits compared() when
  // done. Nothing without levels or while one runs.
  static constexpr int kCompareRepetitions = 5;
  void compare(int frames = 30, int repetitions = kCompareRepetitions);
  bool isComparing() const { return m_compareWatcher.isRunning(); }
  // The last comparison (empty configurations before the first, and once the crowd's inputs
  // changed) and its text (empty then).
  const CrowdComparison& comparison() const { return m_comparison; }
  QString comparisonText() const;
  QString comparisonText(const QString& character, int agents) const; // of comparison()

signals:
  void levelsReady(bool ok, const QString& message);
  void measured(double poseCpuMs, double framesPerSecond);
  void compared(bool ok, const QString& message);

protected:
  void showEvent(QShowEvent* event) override;

private:
  void markDirty();
  void startBuild();
  void onBuilt();
  void placeAgents();
  void frameCrowd();
  void onFrameSwapped();
  void onCompared();
  void clearComparison();

  Document* m_document = nullptr;
  Playback* m_playback = nullptr;
  SceneView* m_view = nullptr;
  QLabel* m_figures = nullptr;
  QLabel* m_legend = nullptr; // the level tints
  QSpinBox* m_agents = nullptr;
  QComboBox* m_layout = nullptr;
  QDoubleSpinBox* m_spacing = nullptr;
  QComboBox* m_selectionMode = nullptr;
  QDoubleSpinBox* m_hysteresis = nullptr;
  QCheckBox* m_tint = nullptr;
  QLabel* m_comparisonLabel = nullptr;
  // what the levels were built from (compare() builds the other configurations' levels)
  struct Source {
    std::shared_ptr<const Skeleton> skeleton;
    std::shared_ptr<const Clip> clip;
    std::shared_ptr<const Asset> asset; // owns the mesh
    const SkinnedMesh* mesh = nullptr;
    LodSet lods;
    JpcSettings jpc;
    QString description; // what the Viewport calls it
  };
  Source m_source;        // of the levels on screen
  Source m_pendingSource; // of the levels being built
  CrowdComparison m_comparison;
  using Compared = std::shared_ptr<Result<CrowdComparison>>;
  QFutureWatcher<Compared> m_compareWatcher;
  std::shared_ptr<std::atomic<bool>> m_compareCancel;
  int m_compareGeneration = 0; // one more each time the comparison is cleared
  int m_comparedGeneration = 0; // of the comparison running
  QString m_comparedCharacter;
  int m_comparedAgents = 0;

  struct Inputs {
    std::shared_ptr<const Asset> asset;
    int clip = -1;
    LodSet lods;
    double alpha = 0.0;
    JpcMode mode = JpcMode::Greedy;
    std::map<std::string, JointSettings> joints;
    int mapping = -1;
    std::vector<ProjectMapping> mappings;
    bool operator==(const Inputs&) const = default;
  };
  Inputs m_inputs; // of the levels built or being built
  int m_mapping = -1;
  Crowd m_crowd;
  std::vector<int> m_meshIds; // per level
  using Built = std::shared_ptr<Result<std::vector<CrowdLevel>>>;
  QFutureWatcher<Built> m_watcher;
  std::shared_ptr<std::atomic<bool>> m_cancel;
  bool m_dirty = true;
  bool m_framed = false;
  QTimer m_rebuildTimer;
  QString m_error;
  QString m_sourceText;
  QStringList m_overlay;
  std::vector<std::vector<SceneView::Instance>> m_instances; // per level

  // frame rate: frames swapped while something changes
  QElapsedTimer m_fpsClock;
  qint64 m_lastSwap = 0; // ns since m_fpsClock started
  int m_fpsFrames = 0;
  double m_fps = 0.0;
  // measure()
  int m_measureLeft = 0;
  int m_measureFrames = 0;
  double m_measurePoseMs = 0.0;
  QElapsedTimer m_measureClock;
};

} // namespace mlod
