#pragma once
// The Viewport, the main window's central widget (docs/architecture.md section 7; the
// paper's Figures 8-12): the asset in view as a skinned character (or bone capsules for a motion without mesh),
// original and simplified side by side or the original as a ghost over the simplified, the skeleton overlay with the
// joints frozen at the current frame highlighted and joint picking, a motion played on the
// character it is mapped to, and the timeline every 3D view follows. Poses come from the
// runtime's PoseEvaluatorJob; SceneView skins them on the GPU.
//
// The simplified character wears its level's mesh, exactly as the level exports it
// (LevelMeshes: built off the UI thread, kept per level); the original wears the
// character's meshes. Until a level's mesh has landed the simplified one wears the original
// and the overlay says so. The overlay gives the triangles and joints each character drawn
// has; W (View > Wireframe) draws the meshes as lines.

#include "core/project.h"
#include "core/jpc/jpc_analysis.h"
#include "editor/viewport/level_meshes.h"
#include "editor/viewport/scene_view.h"
#include "editor/viewport/view_source.h"
#include "runtime/lod_clip.h"
#include "runtime/pose_evaluator.h"
#include "runtime/skinning_job.h"

#include <QWidget>

#include <glm/glm.hpp>

#include <vector>

class QAction;
class QCheckBox;
class QComboBox;
class QLabel;

namespace mlod {

class Document;
class Playback;
class TimelineWidget;

class ViewportPanel : public QWidget {
  Q_OBJECT
public:
  enum class Mode { SideBySide, Ghost, Original, Simplified };

  explicit ViewportPanel(Document* document, QWidget* parent = nullptr);
  ~ViewportPanel() override;

  Playback* playback() const { return m_playback; }
  TimelineWidget* timeline() const { return m_timeline; }
  SceneView* sceneView() const { return m_view; } // null where the platform has no OpenGL
  QComboBox* modeBox() const { return m_modeBox; }
  QComboBox* characterBox() const { return m_characterBox; }
  Mode mode() const;
  void setMode(Mode mode);
  const ViewSource& source() const { return m_source; }
  QString statusText() const; // what the overlay says (also without OpenGL)
  QAction* wireframeAction() const { return m_wireframe; } // checkable, W
  LevelMeshes* levelMeshes() const { return m_levelMeshes; }

  // What each character drawn wears, in drawing order (also without OpenGL).
  struct Drawn {
    bool simplified = false;
    int level = 0;          // the level the simplified one shows (0 for the original)
    bool levelMesh = false; // wears the level's own mesh (else the character's meshes)
    qint64 triangles = 0;   // of the meshes it wears
    int joints = 0;         // of the skeleton that moves them (the level's, after bone reduction)
  };
  const std::vector<Drawn>& drawn() const { return m_drawnNow; }
  // One line per character drawn: "simplified LOD3 372 triangles, 26 joints" (what
  // motionlod-studio --screenshot prints).
  QStringList drawnLines() const;
  // The level in view wants its own mesh and it is still being built.
  bool levelMeshPending() const { return m_levelPending; }

  // The world-space box (cm) that holds the drawn characters in the current pose.
  bool posedBounds(glm::vec3& out_lo, glm::vec3& out_hi) const;
  // World-space joint positions of the drawn instances (original first when both are shown).
  std::vector<glm::vec3> jointPositions(int instance) const;
  int instanceCount() const { return static_cast<int>(m_instances.size()); }
  // The joint nearest to a window position (within 12 pixels), as a joint of the asset in
  // view, or -1. What a click picks.
  int pickJoint(const QPoint& position) const;
  void frameCharacters();

signals:
  // The character the asset in view plays on: an index of project().mappings, or -1.
  void mappingChosen(int mapping);
  // The level in view now wears its own mesh (or failed to get one: the overlay says why).
  void levelMeshReady();

public slots:
  void rebuild(); // the document changed: new source, clips and meshes
  void pose();    // the time changed: evaluate and hand the palettes to the view

private:
  // Asks for the mesh of the level in view and, when it changed, hands the view its meshes.
  void attachLevelMesh();
  void uploadMeshes();

  Document* m_document = nullptr;
  LevelMeshes* m_levelMeshes = nullptr;
  std::shared_ptr<const LevelMeshes::Level> m_level; // the mesh the simplified one wears, or null
  bool m_levelPending = false;
  std::vector<int> m_levelMeshIds;
  std::vector<Drawn> m_drawnNow;
  QAction* m_wireframe = nullptr;
  Playback* m_playback = nullptr;
  TimelineWidget* m_timeline = nullptr;
  SceneView* m_view = nullptr;
  QLabel* m_noGl = nullptr;
  QComboBox* m_modeBox = nullptr;
  QComboBox* m_characterBox = nullptr;
  QCheckBox* m_skeletonBox = nullptr;

  // What the source was made from: the same key gives the same source.
  struct SourceKey {
    std::shared_ptr<const Asset> asset;
    int clip = -1;
    int level = -1;
    int mapping = -1;
    std::shared_ptr<const JpcAnalysis> analysis;
    std::vector<ProjectMapping> mappings;
    bool operator==(const SourceKey&) const = default;
  };
  SourceKey m_key;
  ViewSource m_source;
  LodClip m_originalClip, m_simplifiedClip;
  std::vector<std::int16_t> m_parents;
  std::vector<glm::mat4> m_inverseBinds;
  std::vector<int> m_meshIds;
  std::vector<SkinningMesh> m_skinning; // per drawn mesh, for bounds
  std::vector<SkinnedMesh> m_drawn;     // the meshes as drawn (capsules included)
  PoseEvaluatorContext m_context;
  std::vector<glm::mat4> m_models, m_palettes; // [instance * joints + joint]: 0 original, 1 simplified
  struct Placed {
    int clip = 0; // 0 original, 1 simplified
    glm::vec3 offset{0.0f};
    float alpha = 1.0f;
    glm::vec4 tint{1.0f};
  };
  std::vector<Placed> m_instances;
  float m_sideOffset = 60.0f;
  bool m_valid = false;
  bool m_framed = false;
  const Clip* m_lastClip = nullptr;
  QString m_status;
};

} // namespace mlod
