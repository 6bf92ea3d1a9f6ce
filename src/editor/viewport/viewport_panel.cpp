#include "editor/viewport/viewport_panel.h"

#include "core/crowd/crowd.h"
#include "core/lod_clip_builder.h"
#include "editor/document/document.h"
#include "editor/viewport/playback.h"

#include <QAction>
#include <QCheckBox>
#include <QComboBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QLocale>
#include <QShortcut>
#include <QToolButton>
#include <QVBoxLayout>

#include <algorithm>
#include <cmath>
#include <limits>

namespace mlod {

namespace {

const glm::vec4 kOriginalTint(0.55f, 0.70f, 0.95f, 1.0f);   // cool: the original
const glm::vec4 kSimplifiedTint(0.95f, 0.78f, 0.55f, 1.0f); // warm: the simplified
const glm::vec4 kBoneColor(0.85f, 0.85f, 0.80f, 1.0f);
const glm::vec4 kActiveJoint(0.95f, 0.95f, 0.95f, 1.0f);
const glm::vec4 kFrozenJoint(1.0f, 0.35f, 0.15f, 1.0f);
const glm::vec4 kSelectedJoint(0.2f, 0.9f, 1.0f, 1.0f);

} // namespace

ViewportPanel::ViewportPanel(Document* document, QWidget* parent)
    : QWidget(parent), m_document(document), m_levelMeshes(new LevelMeshes(document, this)),
      m_playback(new Playback(this)) {
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->setSpacing(2);
  auto* bar = new QHBoxLayout;
  bar->setContentsMargins(4, 2, 4, 0);
  m_modeBox = new QComboBox;
  m_modeBox->setObjectName("viewportModeBox");
  m_modeBox->addItem(tr("Side by side"), int(Mode::SideBySide));
  m_modeBox->addItem(tr("Ghost"), int(Mode::Ghost));
  m_modeBox->addItem(tr("Original"), int(Mode::Original));
  m_modeBox->addItem(tr("Simplified"), int(Mode::Simplified));
  m_modeBox->setToolTip(tr("Original (blue) and simplified (orange) side by side, or the original as a ghost over "
                           "the simplified"));
  m_characterBox = new QComboBox;
  m_characterBox->setObjectName("viewportCharacterBox");
  m_characterBox->setToolTip(tr("Play the motion on its own skeleton, or on a character it is mapped to "
                                "(Edit > Assign Motion to Character; Edit > Edit Joint Mapping)"));
  m_skeletonBox = new QCheckBox(tr("Skeleton"));
  m_skeletonBox->setChecked(true);
  m_skeletonBox->setToolTip(tr("Skeleton overlay: joints frozen at this frame in red, the selected joint in cyan; "
                               "click a joint to select it"));
  auto* frame = new QToolButton;
  frame->setText(tr("Frame"));
  frame->setToolTip(tr("Frame the characters (F)"));
  m_wireframe = new QAction(tr("&Wireframe"), this);
  m_wireframe->setObjectName("actionWireframe");
  m_wireframe->setCheckable(true);
  m_wireframe->setShortcut(QKeySequence(Qt::Key_W));
  m_wireframe->setShortcutContext(Qt::WindowShortcut);
  m_wireframe->setToolTip(tr("Draw the characters' meshes as lines, to judge a level's triangles (W)"));
  addAction(m_wireframe); // the shortcut works where the panel stands alone too
  auto* wireframe = new QToolButton;
  wireframe->setObjectName("viewportWireframeButton");
  wireframe->setDefaultAction(m_wireframe);
  bar->addWidget(new QLabel(tr("Show")));
  bar->addWidget(m_modeBox);
  bar->addWidget(new QLabel(tr("on")));
  bar->addWidget(m_characterBox, 1);
  bar->addWidget(m_skeletonBox);
  bar->addWidget(wireframe);
  bar->addWidget(frame);
  layout->addLayout(bar);

  QString reason;
  if (sceneViewSupported(&reason)) {
    m_view = new SceneView;
    m_view->setObjectName("characterView");
    layout->addWidget(m_view, 1);
    connect(m_view, &SceneView::frameRequested, this, &ViewportPanel::frameCharacters);
    connect(m_view, &SceneView::togglePlayRequested, m_playback, &Playback::togglePlaying);
    connect(m_view, &SceneView::clicked, this, [this](const QPoint& position) {
      const int joint = pickJoint(position);
      if (joint >= 0)
        m_document->setCurrentJoint(joint);
    });
  } else {
    m_noGl = new QLabel(reason);
    m_noGl->setObjectName("viewportUnavailable");
    m_noGl->setAlignment(Qt::AlignCenter);
    m_noGl->setWordWrap(true);
    layout->addWidget(m_noGl, 1);
  }
  m_timeline = new TimelineWidget(m_playback);
  m_timeline->addKeys(this);
  layout->addWidget(m_timeline);

  // Space plays and pauses wherever the focus is in this dock (the view, the timeline, the bar).
  auto* play = new QShortcut(QKeySequence(Qt::Key_Space), this, nullptr, nullptr, Qt::WidgetWithChildrenShortcut);
  connect(play, &QShortcut::activated, m_playback, &Playback::togglePlaying);
  connect(frame, &QToolButton::clicked, this, &ViewportPanel::frameCharacters);
  connect(m_modeBox, &QComboBox::currentIndexChanged, this, &ViewportPanel::pose);
  connect(m_skeletonBox, &QCheckBox::toggled, this, &ViewportPanel::pose);
  // the artist's choice goes to the document (the LOD set in view follows it), then the views
  connect(m_characterBox, &QComboBox::currentIndexChanged, this, [this] {
    const int mapping = m_characterBox->currentData().toInt();
    const auto& mappings = m_document->project().mappings;
    m_document->setViewedCharacter(
        mapping >= 0 && mapping < int(mappings.size()) ? mappings[static_cast<std::size_t>(mapping)].character : -1);
    rebuild();
  });
  connect(m_playback, &Playback::timeChanged, this, &ViewportPanel::pose);
  connect(document, &Document::currentChanged, this, &ViewportPanel::rebuild);
  connect(document, &Document::assetsChanged, this, &ViewportPanel::rebuild);
  connect(document, &Document::mappingsChanged, this, &ViewportPanel::rebuild);
  connect(document, &Document::analysisFinished, this, &ViewportPanel::rebuild);
  // a mesh ratio edited leaves the clusters as they are: only the level's mesh changes
  connect(document, &Document::settingsChanged, this, [this] {
    attachLevelMesh();
    pose();
  });
  connect(m_levelMeshes, &LevelMeshes::ready, this, [this](int character, int level) {
    if (!m_valid || character != m_source.characterAsset || level != m_source.level)
      return;
    attachLevelMesh();
    pose();
    emit levelMeshReady();
  });
  connect(m_wireframe, &QAction::toggled, this, [this](bool on) {
    if (m_view)
      m_view->setWireframe(on);
  });
  rebuild();
}

ViewportPanel::~ViewportPanel() = default;

ViewportPanel::Mode ViewportPanel::mode() const { return Mode(m_modeBox->currentData().toInt()); }

void ViewportPanel::setMode(Mode mode) { m_modeBox->setCurrentIndex(m_modeBox->findData(int(mode))); }

QString ViewportPanel::statusText() const { return m_status; }

void ViewportPanel::rebuild() {
  // the characters the asset in view can play on; the chosen one is the document's viewed
  // character (whose LOD set the docks show)
  {
    const QSignalBlocker block(m_characterBox);
    m_characterBox->clear();
    m_characterBox->addItem(tr("its own skeleton"), -1);
    int chosen = 0;
    for (int mapping : mappingsOfCurrentAsset(*m_document)) {
      const ProjectMapping& entry = m_document->project().mappings[static_cast<std::size_t>(mapping)];
      if (entry.character == m_document->viewedCharacter() && chosen == 0)
        chosen = m_characterBox->count();
      m_characterBox->addItem(QString::fromStdString(entry.mapping.characterName), mapping);
    }
    m_characterBox->setCurrentIndex(chosen);
    m_characterBox->setEnabled(m_characterBox->count() > 1);
  }
  if (m_characterBox->currentData().toInt() != m_key.mapping)
    emit mappingChosen(m_characterBox->currentData().toInt());
  // Selecting a joint changes nothing drawn but its highlight: pose again, keep the rest.
  const SourceKey key{m_document->currentAsset() >= 0 && m_document->currentAsset() < m_document->assetCount()
                          ? m_document->asset(m_document->currentAsset())
                          : nullptr,
                      m_document->currentClip(),
                      m_document->currentLevel(),
                      m_characterBox->currentData().toInt(),
                      m_document->analysis(),
                      m_document->project().mappings};
  if (m_valid && key == m_key) {
    // A motion assigned to the character may have landed since (a project imports its assets
    // one by one): the level's mesh is built with it, so ask again (a kept mesh costs nothing).
    attachLevelMesh();
    pose();
    return;
  }
  m_key = key;
  m_source = makeViewSource(*m_document, m_characterBox->currentData().toInt());
  m_valid = false;
  m_instances.clear();
  if (m_view)
    m_view->clearMeshes();
  m_meshIds.clear();
  m_levelMeshIds.clear();
  m_level.reset();
  m_levelPending = false;
  m_drawnNow.clear();
  m_skinning.clear();
  m_drawn.clear();
  if (!m_source.valid()) {
    m_status = m_source.error;
    m_playback->setClip(0, 30.0);
    if (m_view) {
      m_view->setBatches({});
      m_view->setLines({}, {});
      m_view->setOverlay({});
      m_view->setMessage(m_status);
    }
    return;
  }
  Result<LodClip> original = buildLodClip(m_source.original, nullptr, false);
  Result<LodClip> simplified = buildLodClip(m_source.simplified, nullptr, false);
  if (!original || !simplified) {
    m_status = tr("Cannot play this clip: %1").arg(QString::fromStdString((!original ? original : simplified).message()));
    if (m_view)
      m_view->setMessage(m_status);
    return;
  }
  m_originalClip = std::move(original).value();
  m_simplifiedClip = std::move(simplified).value();
  m_parents = m_source.skeleton.parentIndices();
  m_inverseBinds = paletteInverseBinds(m_source.skeleton);
  const int joints = m_source.skeleton.jointCount();
  m_context.resize(2, joints);
  m_models.assign(2 * std::size_t(joints), glm::mat4(1.0f));
  m_palettes.assign(2 * std::size_t(joints), glm::mat4(1.0f));

  // Meshes: the character's, or bone capsules.
  for (const SkinnedMesh* mesh : m_source.meshes)
    m_drawn.push_back(*mesh);
  if (m_drawn.empty()) {
    const std::vector<glm::mat4> rest = m_source.skeleton.restModelMatrices();
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (const glm::mat4& m : rest) {
      lo = glm::min(lo, glm::vec3(m[3]));
      hi = glm::max(hi, glm::vec3(m[3]));
    }
    m_drawn.push_back(boneCapsuleMesh(m_source.skeleton, std::max(0.5f, 0.025f * glm::length(hi - lo))));
  }
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const SkinnedMesh& mesh : m_drawn) {
    for (const glm::vec3& p : mesh.positions) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    std::vector<glm::u16vec4> rigidJoints;
    std::vector<glm::vec4> rigidWeights;
    if (!mesh.skinned()) {
      rigidJoints.assign(mesh.vertexCount(), glm::u16vec4(0));
      rigidWeights.assign(mesh.vertexCount(), glm::vec4(1.0f, 0.0f, 0.0f, 0.0f));
    }
    std::optional<SkinningMesh> skinning =
        SkinningMesh::build(mesh.positions, mesh.normals.size() == mesh.positions.size() ? mesh.normals : std::span<const glm::vec3>(),
                            mesh.skinned() ? std::span<const glm::u16vec4>(mesh.joints) : rigidJoints,
                            mesh.skinned() ? std::span<const glm::vec4>(mesh.weights) : rigidWeights, joints);
    if (skinning)
      m_skinning.push_back(std::move(*skinning));
  }
  uploadMeshes();
  const glm::vec3 extent = m_drawn.front().positions.empty() ? glm::vec3(100.0f) : hi - lo;
  m_sideOffset = 0.5f * std::max(extent.x, extent.z) + 0.15f * std::max({extent.x, extent.y, extent.z}) + 10.0f;
  if (m_view) {
    const float size = std::max({extent.x, extent.y, extent.z, 50.0f});
    float step = 10.0f;
    while (step * 8.0f < size)
      step *= 5.0f;
    m_view->setGrid(std::max(500.0f, 3.0f * size), step);
    m_view->setMessage({});
  }
  m_valid = true;
  attachLevelMesh();
  // the timeline follows the clip in view; a new clip starts at frame 0
  const Clip* clip = m_source.motion && m_document->currentClipPtr() ? m_document->currentClipPtr() : nullptr;
  if (clip != m_lastClip || m_playback->frameCount() != m_source.original.frameCount) {
    m_lastClip = clip;
    m_playback->setClip(m_source.original.frameCount, m_source.original.fps);
    m_playback->setSeconds(0.0);
    m_framed = false;
  }
  pose();
  if (!m_framed && m_view) {
    frameCharacters();
    m_framed = true;
  }
}

void ViewportPanel::uploadMeshes() {
  m_meshIds.clear();
  m_levelMeshIds.clear();
  if (!m_view)
    return;
  m_view->clearMeshes();
  for (const SkinnedMesh& mesh : m_drawn)
    m_meshIds.push_back(m_view->addMesh(mesh));
  if (m_level && m_level->error.isEmpty())
    m_levelMeshIds.push_back(m_view->addMesh(m_level->mesh));
}

void ViewportPanel::attachLevelMesh() {
  if (!m_valid)
    return;
  // Level 0 is the original; a character drawn as bone capsules has no mesh to simplify.
  std::shared_ptr<const LevelMeshes::Level> level;
  // (A level removed a moment ago is asked for by no one: the analysis's rebuild follows.)
  const bool wanted = m_source.level > 0 && m_source.level < m_document->levelCount() && !m_source.meshes.empty() &&
                      m_source.characterAsset >= 0;
  if (wanted)
    level = m_levelMeshes->request(m_source.characterAsset, m_source.level);
  m_levelPending = wanted && !level;
  if (level == m_level)
    return;
  m_level = std::move(level);
  uploadMeshes();
}

QStringList ViewportPanel::drawnLines() const {
  const QLocale locale(QLocale::English);
  const auto& levels = m_document->lods().levels;
  QStringList out;
  for (const Drawn& d : m_drawnNow) {
    const QString name = d.level >= 0 && std::size_t(d.level) < levels.size()
                             ? QString::fromStdString(levels[std::size_t(d.level)].name)
                             : tr("level %1").arg(d.level);
    QString line = d.simplified ? tr("simplified %1").arg(name) : tr("original");
    line += tr(" %1 triangles, %2 joints").arg(locale.toString(d.triangles)).arg(d.joints);
    if (d.simplified && d.level > 0 && !d.levelMesh && !m_source.meshes.empty())
      line += m_levelPending ? tr(" (the original mesh: the level's mesh is being built)")
                             : tr(" (the original mesh: %1)").arg(m_level ? m_level->error : tr("no level mesh"));
    out << line;
  }
  return out;
}

void ViewportPanel::pose() {
  if (!m_valid)
    return;
  const int joints = m_source.skeleton.jointCount();
  const double seconds = std::clamp(m_playback->seconds(), 0.0, m_originalClip.duration());
  const LodClip* clips[2] = {&m_originalClip, &m_simplifiedClip};
  const double times[2] = {seconds, std::min(seconds, m_simplifiedClip.duration())};
  PoseEvaluatorJob job;
  job.parents = m_parents;
  job.inverseBinds = m_inverseBinds;
  job.clips = clips;
  job.times = times;
  job.context = &m_context;
  job.out_models = m_models;
  job.out_palette = m_palettes;
  if (!job.run()) {
    m_status = tr("The pose evaluator refused this clip.");
    if (m_view)
      m_view->setMessage(m_status);
    return;
  }

  m_instances.clear();
  switch (mode()) {
  case Mode::SideBySide:
    m_instances.push_back({0, glm::vec3(-m_sideOffset, 0.0f, 0.0f), 1.0f, kOriginalTint});
    m_instances.push_back({1, glm::vec3(m_sideOffset, 0.0f, 0.0f), 1.0f, kSimplifiedTint});
    break;
  case Mode::Ghost:
    m_instances.push_back({1, glm::vec3(0.0f), 1.0f, kSimplifiedTint});
    m_instances.push_back({0, glm::vec3(0.0f), 0.35f, kOriginalTint});
    break;
  case Mode::Original:
    m_instances.push_back({0, glm::vec3(0.0f), 1.0f, kOriginalTint});
    break;
  case Mode::Simplified:
    m_instances.push_back({1, glm::vec3(0.0f), 1.0f, kSimplifiedTint});
    break;
  }

  const int frame = m_playback->frame();
  const std::vector<bool> frozen = m_source.frozenAt(frame);
  const int frozenCount = static_cast<int>(std::count(frozen.begin(), frozen.end(), true));
  const QString level =
      m_source.simplifiedReady
          ? tr("level %1 (%2)")
                .arg(m_source.level)
                .arg(QString::fromStdString(m_document->lods().levels[std::size_t(m_source.level)].name))
          : tr("level %1 (clustering…)").arg(m_source.level);
  m_status = tr("%1 · %2 · frame %3 · %4 of %5 joints frozen")
                 .arg(m_source.description, level)
                 .arg(frame)
                 .arg(frozenCount)
                 .arg(joints);
  // what each character drawn wears
  qint64 originalTriangles = 0;
  for (const SkinnedMesh& mesh : m_drawn)
    originalTriangles += qint64(mesh.triangleCount());
  const bool levelMesh = m_level && m_level->error.isEmpty();
  m_drawnNow.clear();
  for (const Placed& placed : m_instances) {
    Drawn d;
    d.simplified = placed.clip == 1;
    d.level = d.simplified ? m_source.level : 0;
    d.levelMesh = d.simplified && levelMesh;
    d.triangles = d.levelMesh ? qint64(m_level->mesh.triangleCount()) : originalTriangles;
    d.joints = d.levelMesh ? m_level->joints : joints;
    m_drawnNow.push_back(d);
  }
  if (!m_view)
    return;

  // Instances: one batch per (mesh, instance), so that each instance has its own palette.
  std::vector<SceneView::Instance> placed(m_instances.size());
  std::vector<SceneView::Batch> batches;
  for (std::size_t i = 0; i < m_instances.size(); ++i) {
    placed[i].position = m_instances[i].offset;
    placed[i].tint = m_instances[i].tint;
    const bool wearsLevel = m_drawnNow[i].levelMesh && !m_levelMeshIds.empty();
    for (int mesh : wearsLevel ? m_levelMeshIds : m_meshIds) {
      SceneView::Batch batch;
      batch.mesh = mesh;
      batch.joints = joints;
      batch.palettes = std::span<const glm::mat4>(m_palettes).subspan(std::size_t(m_instances[i].clip) * joints, joints);
      batch.instances = std::span<const SceneView::Instance>(placed).subspan(i, 1);
      batch.alpha = m_instances[i].alpha;
      batches.push_back(batch);
    }
  }
  m_view->setBatches(batches);

  std::vector<SceneView::LineVertex> lines, points;
  if (m_skeletonBox->isChecked()) {
    const int selected = m_document->currentJoint();
    for (std::size_t i = 0; i < m_instances.size(); ++i) {
      if (m_instances[i].alpha < 1.0f)
        continue; // the ghost's skeleton would hide the simplified one's
      const std::vector<glm::vec3> positions = jointPositions(static_cast<int>(i));
      for (int j = 0; j < joints; ++j) {
        const int parent = m_parents[std::size_t(j)];
        if (parent >= 0) {
          lines.push_back({positions[std::size_t(parent)], kBoneColor});
          lines.push_back({positions[std::size_t(j)], kBoneColor});
        }
        const bool isSelected = selected >= 0 && m_source.motionJoint[std::size_t(j)] == selected;
        const bool isFrozen = m_instances[i].clip == 1 && frozen[std::size_t(j)];
        points.push_back({positions[std::size_t(j)], isSelected ? kSelectedJoint : (isFrozen ? kFrozenJoint : kActiveJoint)});
      }
    }
  }
  m_view->setLines(std::move(lines), std::move(points));
  QStringList overlay{m_status};
  overlay << drawnLines();
  overlay << tr("blue: original · orange: simplified · red joints: frozen at this frame");
  m_view->setOverlay(overlay);
}

std::vector<glm::vec3> ViewportPanel::jointPositions(int instance) const {
  std::vector<glm::vec3> out;
  if (!m_valid || instance < 0 || instance >= instanceCount())
    return out;
  const Placed& placed = m_instances[std::size_t(instance)];
  const std::size_t joints = m_parents.size();
  for (std::size_t j = 0; j < joints; ++j)
    out.push_back(glm::vec3(m_models[std::size_t(placed.clip) * joints + j][3]) + placed.offset);
  return out;
}

bool ViewportPanel::posedBounds(glm::vec3& out_lo, glm::vec3& out_hi) const {
  if (!m_valid || m_instances.empty())
    return false;
  out_lo = glm::vec3(std::numeric_limits<float>::max());
  out_hi = glm::vec3(-std::numeric_limits<float>::max());
  const std::size_t joints = m_parents.size();
  std::vector<glm::vec3> positions, normals;
  for (const Placed& placed : m_instances) {
    const std::span<const glm::mat4> palette =
        std::span<const glm::mat4>(m_palettes).subspan(std::size_t(placed.clip) * joints, joints);
    for (const SkinningMesh& mesh : m_skinning) {
      positions.resize(std::size_t(mesh.vertexCount()));
      normals.resize(mesh.hasNormals() ? std::size_t(mesh.vertexCount()) : 0);
      if (!mesh.skin(palette, positions, normals))
        continue;
      for (const glm::vec3& p : positions) {
        out_lo = glm::min(out_lo, p + placed.offset);
        out_hi = glm::max(out_hi, p + placed.offset);
      }
    }
  }
  return out_lo.x <= out_hi.x;
}

int ViewportPanel::pickJoint(const QPoint& position) const {
  if (!m_view || !m_valid)
    return -1;
  float best = 12.0f;
  int picked = -1;
  for (int i = 0; i < instanceCount(); ++i) {
    const std::vector<glm::vec3> joints = jointPositions(i);
    for (std::size_t j = 0; j < joints.size(); ++j) {
      glm::vec2 pixel;
      if (!m_view->camera().project(joints[j], float(m_view->width()), float(m_view->height()), pixel))
        continue;
      const float d = glm::length(pixel - glm::vec2(position.x(), position.y()));
      if (d < best && m_source.motionJoint[j] >= 0) {
        best = d;
        picked = m_source.motionJoint[j];
      }
    }
  }
  return picked;
}

void ViewportPanel::frameCharacters() {
  glm::vec3 lo, hi;
  if (!m_view || !posedBounds(lo, hi))
    return;
  m_view->camera().frame(lo, hi);
  m_view->update();
}

} // namespace mlod
