#include "editor/viewport/crowd_panel.h"

#include "editor/document/document.h"
#include "editor/viewport/playback.h"
#include "editor/viewport/view_source.h"

#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFileInfo>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QLocale>
#include <QSpinBox>
#include <QToolButton>
#include <QVBoxLayout>
#include <QtConcurrent/QtConcurrentRun>

#include <algorithm>
#include <cmath>
#include <limits>

namespace mlod {

glm::vec4 crowdLevelTint(int level) {
  static const glm::vec4 kTints[] = {
      {0.15f, 0.85f, 0.25f, 1.0f}, // green
      {0.95f, 0.90f, 0.10f, 1.0f}, // yellow
      {1.00f, 0.45f, 0.05f, 1.0f}, // orange
      {0.95f, 0.12f, 0.12f, 1.0f}, // red
      {0.85f, 0.15f, 0.90f, 1.0f}, // magenta
      {0.15f, 0.40f, 1.00f, 1.0f}, // blue
      {0.10f, 0.90f, 0.90f, 1.0f}, // cyan
  };
  const int n = static_cast<int>(std::size(kTints));
  return kTints[std::clamp(level, 0, 1 << 20) % n];
}

CrowdPanel::CrowdPanel(Document* document, Playback* playback, QWidget* parent)
    : QWidget(parent), m_document(document), m_playback(playback) {
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->setSpacing(2);
  auto* bar = new QHBoxLayout;
  bar->setContentsMargins(4, 2, 4, 0);
  m_agents = new QSpinBox;
  m_agents->setObjectName("crowdAgentsBox");
  m_agents->setRange(1, kMaxCrowdAgents);
  m_agents->setValue(100);
  m_agents->setKeyboardTracking(false);
  m_agents->setToolTip(tr("Agents in the crowd (1 to %1)").arg(kMaxCrowdAgents));
  m_layout = new QComboBox;
  m_layout->setObjectName("crowdLayoutBox");
  m_layout->addItem(tr("Grid"), int(CrowdLayout::Kind::Grid));
  m_layout->addItem(tr("Scattered"), int(CrowdLayout::Kind::Scattered));
  m_layout->setToolTip(tr("Agents on a grid, or scattered over the same square with random headings"));
  m_spacing = new QDoubleSpinBox;
  m_spacing->setRange(30.0, 5000.0);
  m_spacing->setValue(200.0);
  m_spacing->setSuffix(tr(" cm"));
  m_spacing->setDecimals(0);
  m_spacing->setKeyboardTracking(false);
  m_spacing->setToolTip(tr("Grid step between agents"));
  m_selectionMode = new QComboBox;
  m_selectionMode->setObjectName("crowdSelectionBox");
  m_selectionMode->addItem(tr("By distance"), int(LodSelectionJob::Mode::Distance));
  m_selectionMode->addItem(tr("By screen size"), int(LodSelectionJob::Mode::ScreenSize));
  m_selectionMode->setToolTip(tr("Pick each agent's level by its distance to the camera or by its projected size, "
                                 "with the LOD set's switch distances or sizes (LOD Levels dock)"));
  m_hysteresis = new QDoubleSpinBox;
  m_hysteresis->setRange(0.0, 0.5);
  m_hysteresis->setSingleStep(0.05);
  m_hysteresis->setValue(0.1);
  m_hysteresis->setToolTip(tr("Hysteresis: an agent switches only once it is this fraction past a boundary"));
  m_tint = new QCheckBox(tr("Tint by level"));
  m_tint->setObjectName("crowdTintBox");
  m_tint->setChecked(true);
  m_tint->setToolTip(tr("Colour each agent by its LOD level: green, yellow, orange, red, magenta … (level 0 first)"));
  auto* frame = new QToolButton;
  frame->setText(tr("Frame"));
  frame->setToolTip(tr("Look at the whole crowd (F)"));
  auto* compareButton = new QToolButton;
  compareButton->setObjectName("crowdCompareButton");
  compareButton->setText(tr("Compare"));
  compareButton->setToolTip(tr("What the LOD set buys on this crowd (the paper's Figure 12): the frame time of pose "
                               "evaluation and CPU skinning with no simplification, skeletal only, mesh only and both, "
                               "same agents, camera and time"));
  // Two rows, so that the dock fits beside the central character view (docs/architecture.md
  // section 7): the crowd, then how it is looked at.
  for (QWidget* w : std::initializer_list<QWidget*>{m_agents, m_layout, m_spacing, m_selectionMode})
    bar->addWidget(w);
  bar->addStretch(1);
  layout->addLayout(bar);
  auto* view = new QHBoxLayout;
  view->setContentsMargins(4, 0, 4, 0);
  view->addWidget(new QLabel(tr("hysteresis")));
  view->addWidget(m_hysteresis);
  view->addWidget(m_tint);
  view->addWidget(frame);
  view->addWidget(compareButton);
  view->addStretch(1);
  layout->addLayout(view);

  QString reason;
  if (sceneViewSupported(&reason)) {
    m_view = new SceneView;
    m_view->setObjectName("crowdView");
    layout->addWidget(m_view, 1);
    connect(m_view, &SceneView::cameraChanged, this, &CrowdPanel::refresh);
    connect(m_view, &SceneView::frameRequested, this, &CrowdPanel::frameCrowd);
    connect(m_view, &SceneView::togglePlayRequested, playback, &Playback::togglePlaying);
    connect(m_view, &QOpenGLWidget::frameSwapped, this, &CrowdPanel::onFrameSwapped);
  } else {
    auto* label = new QLabel(reason);
    label->setObjectName("crowdUnavailable");
    label->setAlignment(Qt::AlignCenter);
    label->setWordWrap(true);
    layout->addWidget(label, 1);
  }
  m_figures = new QLabel;
  m_figures->setObjectName("crowdFigures");
  m_figures->setWordWrap(true);
  m_figures->setTextInteractionFlags(Qt::TextSelectableByMouse);
  m_figures->setToolTip(tr("Agents per level; joints whose local matrix was computed this frame against an all "
                           "full-detail crowd; vertices skinned (each agent's level mesh); CPU time of level selection "
                           "and pose evaluation; frames per second while the view changes"));
  layout->addWidget(m_figures);
  m_legend = new QLabel;
  m_legend->setObjectName("crowdLegend");
  m_legend->setToolTip(tr("The tint of each LOD level's agents"));
  layout->addWidget(m_legend);
  m_comparisonLabel = new QLabel;
  m_comparisonLabel->setObjectName("crowdComparison");
  m_comparisonLabel->setWordWrap(true);
  m_comparisonLabel->setTextInteractionFlags(Qt::TextSelectableByMouse);
  m_comparisonLabel->setVisible(false);
  m_comparisonLabel->setToolTip(tr("Each configuration's frame time, and none's time over it (×), repetition by "
                                   "repetition (the four run in turn, so a repetition's four share the machine's "
                                   "load): the median and, in brackets, the range. A wide range says the machine "
                                   "was busy: compare again."));
  layout->addWidget(m_comparisonLabel);
  connect(compareButton, &QToolButton::clicked, this, [this] { compare(); });
  connect(&m_compareWatcher, &QFutureWatcher<Compared>::finished, this, &CrowdPanel::onCompared);

  m_rebuildTimer.setSingleShot(true);
  m_rebuildTimer.setInterval(250);
  connect(&m_rebuildTimer, &QTimer::timeout, this, &CrowdPanel::startBuild);
  connect(&m_watcher, &QFutureWatcher<Built>::finished, this, &CrowdPanel::onBuilt);
  connect(frame, &QToolButton::clicked, this, &CrowdPanel::frameCrowd);
  connect(m_agents, &QSpinBox::valueChanged, this, &CrowdPanel::placeAgents);
  connect(m_layout, &QComboBox::currentIndexChanged, this, &CrowdPanel::placeAgents);
  connect(m_spacing, &QDoubleSpinBox::valueChanged, this, &CrowdPanel::placeAgents);
  connect(m_selectionMode, &QComboBox::currentIndexChanged, this, &CrowdPanel::refresh);
  connect(m_hysteresis, &QDoubleSpinBox::valueChanged, this, &CrowdPanel::refresh);
  connect(m_tint, &QCheckBox::toggled, this, &CrowdPanel::refresh);
  connect(playback, &Playback::timeChanged, this, &CrowdPanel::refresh);
  // what the levels are built from
  connect(document, &Document::currentChanged, this, &CrowdPanel::markDirty);
  connect(document, &Document::assetsChanged, this, &CrowdPanel::markDirty);
  connect(document, &Document::settingsChanged, this, &CrowdPanel::markDirty);
  connect(document, &Document::mappingsChanged, this, &CrowdPanel::markDirty);
  // a job the artist waits for has the cores first: a running build is cancelled and made
  // again after it
  connect(document, &Document::waitedJobChanged, this, [this](bool running) {
    if (running && m_watcher.isRunning()) {
      m_dirty = true;
      if (m_cancel)
        m_cancel->store(true);
    } else if (!running && m_dirty && isVisible()) {
      m_rebuildTimer.start(0);
    }
  });
  m_figures->setText(tr("The crowd builds its levels when this dock is shown."));
}

CrowdPanel::~CrowdPanel() {
  if (m_cancel)
    m_cancel->store(true);
  if (m_compareCancel)
    m_compareCancel->store(true);
  m_watcher.waitForFinished();
  m_compareWatcher.waitForFinished();
}

void CrowdPanel::compare(int frames, int repetitions) {
  if (!hasLevels() || m_compareWatcher.isRunning() || !m_source.skeleton)
    return;
  const Source source = m_source;
  const std::vector<CrowdAgent> agents = m_crowd.agents();
  const glm::vec3 camera = m_view ? m_view->camera().eye() : crowdFrontCamera(agents);
  float top = 0.0f;
  for (const glm::vec3& p : m_crowd.level(0).mesh.positions)
    top = std::max(top, p.y);
  CrowdComparisonSettings settings;
  settings.frames = std::max(frames, 1);
  settings.repetitions = std::max(repetitions, 1);
  settings.startSeconds = m_playback ? m_playback->seconds() : 0.0;
  settings.centreHeightCm = 0.5f * top;
  settings.jpc = source.jpc;
  m_compareCancel = std::make_shared<std::atomic<bool>>(false);
  std::shared_ptr<std::atomic<bool>> cancel = m_compareCancel;
  m_comparedGeneration = m_compareGeneration;
  m_comparedCharacter = source.description;
  m_comparedAgents = static_cast<int>(agents.size());
  m_comparisonLabel->setVisible(true);
  m_comparisonLabel->setText(tr("Comparing none / skeletal / mesh / both on %1 agents of %2, %3 repetitions …")
                                 .arg(agents.size())
                                 .arg(source.description)
                                 .arg(settings.repetitions));
  m_compareWatcher.setFuture(QtConcurrent::run([source, agents, camera, settings, cancel]() -> Compared {
    CrowdComparisonSettings withCancel = settings;
    withCancel.cancel = cancel.get();
    return std::make_shared<Result<CrowdComparison>>(compareCrowdConfigurations(
        *source.skeleton, source.mesh, *source.clip, source.lods, agents, camera, withCancel));
  }));
}

QString CrowdPanel::comparisonText() const { return m_comparisonLabel->text(); }

void CrowdPanel::onCompared() {
  const Compared result = m_compareWatcher.result();
  if (m_comparedGeneration != m_compareGeneration)
    return; // of a crowd no longer on screen: cleared already
  if (!result || !*result) {
    const QString message = result ? QString::fromStdString(result->message()) : tr("no result");
    m_comparisonLabel->setText(tr("Cannot compare: %1").arg(message));
    emit compared(false, message);
    return;
  }
  m_comparison = **result;
  m_comparisonLabel->setText(comparisonText(m_comparedCharacter, m_comparedAgents));
  emit compared(true, {});
}

QString CrowdPanel::comparisonText(const QString& character, int agents) const {
  // median (min–max) of the repetitions: the frame time of each, and for the three
  // simplified ones none's time over theirs, paired repetition by repetition
  QStringList parts;
  int repetitions = 0;
  for (int c = 0; c < 4; ++c) {
    const CrowdComparison::Spread ms = m_comparison.frameMsSpread(c);
    repetitions = std::max(repetitions, ms.samples);
    QString part = tr("%1 %2 ms (%3–%4)")
                       .arg(QString::fromLatin1(m_comparison.configurations[c].name))
                       .arg(ms.median, 0, 'f', 2)
                       .arg(ms.min, 0, 'f', 2)
                       .arg(ms.max, 0, 'f', 2);
    if (c > 0) {
      const CrowdComparison::Spread x = m_comparison.speedupSpread(c);
      part += tr(" %1× (%2–%3×)").arg(x.median, 0, 'f', 2).arg(x.min, 0, 'f', 2).arg(x.max, 0, 'f', 2);
    }
    parts << part;
  }
  return tr("%1, %2 agents, pose + CPU skinning per frame, median (range) of %3 repetitions: %4")
      .arg(character)
      .arg(agents)
      .arg(repetitions)
      .arg(parts.join(QStringLiteral(" · ")));
}

void CrowdPanel::clearComparison() {
  ++m_compareGeneration;
  if (m_compareCancel)
    m_compareCancel->store(true);
  m_comparison = {};
  m_comparisonLabel->clear();
  m_comparisonLabel->setVisible(false);
}

void CrowdPanel::setAgentCount(int agents) { m_agents->setValue(agents); }

void CrowdPanel::setMapping(int mapping) {
  m_mapping = mapping;
  markDirty();
}

void CrowdPanel::showEvent(QShowEvent* event) {
  QWidget::showEvent(event);
  if (m_dirty)
    requestLevels();
}

void CrowdPanel::markDirty() {
  // Only what the levels are built from counts (the level or joint in view does not).
  const Document& d = *m_document;
  const int asset = d.currentAsset();
  Inputs inputs{asset >= 0 && asset < d.assetCount() ? d.asset(asset) : nullptr,
                d.currentClip(),
                d.lods(),
                d.project().alpha,
                d.project().mode,
                asset >= 0 && asset < d.assetCount() ? d.project().assets[std::size_t(asset)].joints
                                                     : std::map<std::string, JointSettings>(),
                m_mapping,
                d.project().mappings};
  const bool changed = !(inputs == m_inputs);
  if (hasLevels() && !m_dirty && !changed)
    return;
  if (changed) // a comparison of other levels, another character or clip says nothing of these
    clearComparison();
  m_inputs = std::move(inputs);
  m_dirty = true;
  if (isVisible())
    m_rebuildTimer.start();
}

void CrowdPanel::requestLevels() {
  m_dirty = true;
  m_rebuildTimer.start(0);
}

void CrowdPanel::startBuild() {
  if (m_document->isWaitedJobRunning()) { // built when the job ends (waitedJobChanged)
    m_dirty = true;
    return;
  }
  if (m_watcher.isRunning()) { // the running one is stale: cancel it and come back
    if (m_cancel)
      m_cancel->store(true);
    m_rebuildTimer.start();
    return;
  }
  m_dirty = false;
  const ViewSource source = makeViewSource(*m_document, m_mapping);
  if (!source.valid() || source.original.frameCount < 1) {
    m_error = source.valid() ? tr("The asset in view has no clip.") : source.error;
    m_figures->setText(m_error);
    m_crowd.setLevels({});
    if (m_view) {
      m_view->clearMeshes();
      m_view->setBatches({});
      m_view->setMessage(m_error);
    }
    emit levelsReady(false, m_error);
    return;
  }
  auto skeleton = std::make_shared<Skeleton>(source.skeleton);
  auto clip = std::make_shared<Clip>(source.original);
  std::shared_ptr<const Asset> asset = source.character;
  const SkinnedMesh* mesh = nullptr;
  for (const SkinnedMesh* candidate : source.meshes)
    if (candidate->skinned()) {
      mesh = candidate;
      break;
    }
  const LodSet lods = m_document->lods();
  const JpcSettings jpc = m_document->project().jpcSettings(source.characterAsset, asset->unitScale);
  m_cancel = std::make_shared<std::atomic<bool>>(false);
  std::shared_ptr<std::atomic<bool>> cancel = m_cancel;
  m_sourceText = source.description;
  m_figures->setText(tr("Building %1 LOD levels of %2 …").arg(lods.levels.size()).arg(source.description));
  if (m_view)
    m_view->setMessage(tr("Building the LOD levels …"));
  const QString character = QFileInfo(QString::fromStdString(asset->sourcePath)).fileName();
  m_pendingSource = {skeleton, clip, asset, mesh, lods, jpc, tr("%1: %2").arg(character, source.description)};
  m_watcher.setFuture(QtConcurrent::run([skeleton, clip, asset, mesh, lods, jpc, cancel]() -> Built {
    return std::make_shared<Result<std::vector<CrowdLevel>>>(
        buildCrowdLevels(*skeleton, mesh, *clip, lods, jpc, cancel.get()));
  }));
}

void CrowdPanel::onBuilt() {
  const Built built = m_watcher.result();
  if (m_dirty || !built) { // inputs changed meanwhile: build again
    m_rebuildTimer.start();
    return;
  }
  if (!*built) {
    m_error = QString::fromStdString(built->message());
    if (m_error == QLatin1String("cancelled"))
      return;
    m_figures->setText(tr("Cannot build the crowd: %1").arg(m_error));
    if (m_view)
      m_view->setMessage(m_figures->text());
    emit levelsReady(false, m_error);
    return;
  }
  m_error.clear();
  m_source = m_pendingSource;
  m_crowd.setLevels(std::move(**built));
  m_crowd.setSwitches(lodSwitchesByDistance(m_document->lods()), lodSwitchesByScreenSize(m_document->lods()));
  // the point whose distance picks the level: half the character's height
  const CrowdLevel& original = m_crowd.level(0);
  float top = 0.0f;
  for (const glm::vec3& p : original.mesh.positions)
    top = std::max(top, p.y);
  m_crowd.setCentreHeight(0.5f * top);
  if (m_view) {
    m_view->clearMeshes();
    m_view->setMessage({});
    m_meshIds.clear();
    for (int l = 0; l < m_crowd.levelCount(); ++l)
      m_meshIds.push_back(m_view->addMesh(m_crowd.level(l).mesh));
  }
  placeAgents();
  emit levelsReady(true, {});
}

void CrowdPanel::placeAgents() {
  if (!hasLevels())
    return;
  CrowdLayout layout;
  layout.kind = CrowdLayout::Kind(m_layout->currentData().toInt());
  layout.agents = m_agents->value();
  layout.spacingCm = static_cast<float>(m_spacing->value());
  m_crowd.setAgents(layoutCrowd(layout, m_crowd.level(0).clip.duration()));
  if (m_view) {
    const float side = layout.spacingCm * std::ceil(std::sqrt(float(layout.agents)));
    float step = 100.0f;
    while (step * 40.0f < side)
      step *= 2.0f;
    m_view->setGrid(0.5f * side + 400.0f, step);
  }
  if (!m_framed) {
    frameCrowd();
    m_framed = true;
  }
  refresh();
}

void CrowdPanel::frameCrowd() {
  if (!m_view || m_crowd.agentCount() == 0)
    return;
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const CrowdAgent& agent : m_crowd.agents()) {
    lo = glm::min(lo, agent.position);
    hi = glm::max(hi, agent.position + glm::vec3(0.0f, 180.0f, 0.0f));
  }
  // Stand just in front of the crowd, at head height, looking in along +Z: the nearest
  // agents are a few metres away and the farthest at the far edge, so that the distances
  // span the LOD set.
  OrbitCamera& camera = m_view->camera();
  camera.yawRadians = 3.14159265f;
  camera.pitchRadians = -0.3f;
  camera.distance = 900.0f;
  camera.target = glm::vec3(0.5f * (lo.x + hi.x), 0.0f, lo.z + 600.0f);
  refresh();
}

void CrowdPanel::refresh() {
  if (!hasLevels() || m_crowd.agentCount() == 0)
    return;
  Crowd::Selection selection;
  selection.mode = LodSelectionJob::Mode(m_selectionMode->currentData().toInt());
  selection.hysteresis = static_cast<float>(m_hysteresis->value());
  selection.projection.verticalFovRadians =
      static_cast<float>(m_document->lods().projection.verticalFovDegrees * 3.14159265358979 / 180.0);
  selection.projection.viewportHeightPixels = static_cast<float>(m_document->lods().projection.viewportHeightPixels);
  selection.boundingRadiusCm = static_cast<float>(std::max(1.0, m_document->lods().boundingRadiusCm));
  m_crowd.setSelection(selection);
  const glm::vec3 eye = m_view ? m_view->camera().eye() : glm::vec3(0.0f, 170.0f, -1000.0f);
  if (Error error = m_crowd.update(m_playback->seconds(), eye)) {
    m_error = QString::fromStdString(error.message());
    m_figures->setText(m_error);
    return;
  }
  const CrowdFrameStats& stats = m_crowd.stats();
  const QLocale locale(QLocale::English);
  QStringList perLevel;
  for (int l = 0; l < m_crowd.levelCount(); ++l)
    perLevel << tr("%1 %2")
                    .arg(QString::fromStdString(m_document->lods().levels.size() > std::size_t(l)
                                                    ? m_document->lods().levels[std::size_t(l)].name
                                                    : "LOD" + std::to_string(l)))
                    .arg(stats.agentsPerLevel[std::size_t(l)]);
  const double jointShare =
      stats.jointsFullDetail > 0 ? 100.0 * double(stats.jointsEvaluated) / double(stats.jointsFullDetail) : 0.0;
  m_overlay = {tr("%1 agents · %2").arg(m_crowd.agentCount()).arg(perLevel.join(QStringLiteral(" · "))),
               tr("joints evaluated %1 / %2 at full detail (%3%)")
                   .arg(locale.toString(qlonglong(stats.jointsEvaluated)), locale.toString(qlonglong(stats.jointsFullDetail)))
                   .arg(jointShare, 0, 'f', 1),
               tr("vertices skinned %1").arg(locale.toString(qlonglong(stats.verticesSkinned))),
               tr("pose evaluation %1 ms CPU · %2 fps")
                   .arg(stats.poseCpuMs, 0, 'f', 2)
                   .arg(m_fps > 0.0 ? QString::number(m_fps, 'f', 1) : QStringLiteral("–"))};
  const bool bySize = selection.mode == LodSelectionJob::Mode::ScreenSize;
  const LodSet& lods = m_document->lods();
  if (lods.levels.size() > 1 && (bySize ? lodSwitchesByScreenSize(lods) : lodSwitchesByDistance(lods)).levels.size() < 2)
    m_overlay << (bySize ? tr("The LOD set has no screen sizes: every agent plays level 0 (generate the levels: LOD "
                              "Levels dock, Budget…)")
                         : tr("The LOD set has no switch distances yet: every agent plays the last level (LOD Levels "
                              "dock, Budget…)"));
  m_figures->setText(m_overlay.join(QStringLiteral("\n")));
  QStringList legend; // each level's tint, as the agents wear it
  for (int l = 0; l < m_crowd.levelCount() && m_tint->isChecked(); ++l)
    legend << QStringLiteral("<span style='color:%1'>■</span> %2")
                  .arg(QColor::fromRgbF(crowdLevelTint(l).x, crowdLevelTint(l).y, crowdLevelTint(l).z).name(),
                       QString::fromStdString(std::size_t(l) < m_document->lods().levels.size()
                                                  ? m_document->lods().levels[std::size_t(l)].name
                                                  : "LOD" + std::to_string(l))
                           .toHtmlEscaped());
  m_legend->setText(legend.join(QStringLiteral("&nbsp;&nbsp; ")));
  if (!m_view)
    return;

  m_instances.assign(std::size_t(m_crowd.levelCount()), {});
  std::vector<SceneView::Batch> batches;
  for (int l = 0; l < m_crowd.levelCount(); ++l) {
    const std::span<const int> agents = m_crowd.levelAgents(l);
    if (agents.empty())
      continue;
    std::vector<SceneView::Instance>& instances = m_instances[std::size_t(l)];
    instances.resize(agents.size());
    const glm::vec4 tint = m_tint->isChecked() ? crowdLevelTint(l) : glm::vec4(0.78f, 0.78f, 0.78f, 1.0f);
    for (std::size_t k = 0; k < agents.size(); ++k) {
      const CrowdAgent& agent = m_crowd.agents()[std::size_t(agents[k])];
      instances[k] = {agent.position, agent.yawRadians, tint};
    }
    SceneView::Batch batch;
    batch.mesh = m_meshIds[std::size_t(l)];
    batch.joints = m_crowd.level(l).skeleton.jointCount();
    batch.palettes = m_crowd.levelPalettes(l);
    batch.instances = instances;
    batches.push_back(batch);
  }
  m_view->setBatches(batches);
  m_view->setOverlay(m_overlay);
}

void CrowdPanel::onFrameSwapped() {
  // Frames per second over runs of 10 frames; a pause of more than 2 s between two frames
  // (nothing changed meanwhile) starts a new run.
  const qint64 now = m_fpsClock.isValid() ? m_fpsClock.nsecsElapsed() : 0;
  if (!m_fpsClock.isValid() || now - m_lastSwap > 2'000'000'000) {
    m_fpsClock.start();
    m_lastSwap = 0;
    m_fpsFrames = 0;
  } else {
    m_lastSwap = now;
    if (++m_fpsFrames >= 10) {
      m_fps = 1e9 * m_fpsFrames / std::max<qint64>(1, now);
      m_fpsClock.start();
      m_lastSwap = 0;
      m_fpsFrames = 0;
    }
  }
  if (m_measureLeft > 0) {
    m_measurePoseMs += m_crowd.stats().poseCpuMs;
    ++m_measureFrames;
    if (--m_measureLeft == 0) {
      const double seconds = m_measureClock.nsecsElapsed() / 1e9;
      const double fps = seconds > 0.0 ? m_measureFrames / seconds : 0.0;
      m_fps = fps;
      refresh(); // the overlay with the measured rate
      emit measured(m_measurePoseMs / std::max(1, m_measureFrames), fps);
      return;
    }
    m_playback->advance(1.0 / 60.0); // timeChanged -> refresh -> the next frame
    if (m_playback->duration() <= 0.0)
      refresh();
  }
}

void CrowdPanel::measure(int frames) {
  m_measureLeft = std::max(1, frames);
  m_measureFrames = 0;
  m_measurePoseMs = 0.0;
  m_measureClock.start();
  m_playback->setPlaying(false);
  if (!m_view) { // no frames to swap: time the poses alone
    for (int f = 0; f < m_measureLeft; ++f) {
      m_playback->advance(1.0 / 60.0);
      m_measurePoseMs += m_crowd.stats().poseCpuMs;
    }
    emit measured(m_measurePoseMs / m_measureLeft, 0.0);
    m_measureLeft = 0;
    return;
  }
  m_playback->advance(1.0 / 60.0);
}

} // namespace mlod
