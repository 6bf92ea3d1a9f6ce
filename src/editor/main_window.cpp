#include "editor/main_window.h"

#include "core/lod/lod_levels.h"
#include "core/project.h"
#include "core/version.h"
#include "editor/charts/statistics_view.h"
#include "editor/document/autosave.h"
#include "editor/document/document.h"
#include "editor/document/edits.h"
#include "editor/document/level_generator.h"
#include "editor/import_job.h"
#include "editor/models/asset_tree.h"
#include "editor/models/joint_tree_model.h"
#include "editor/models/levels_model.h"
#include "editor/studio/window_fit.h"
#include "editor/viewport/crowd_panel.h"
#include "editor/viewport/playback.h"
#include "editor/viewport/viewport_panel.h"
#include "editor/views/budget_dialog.h"
#include "editor/views/clustering_table_view.h"
#include "editor/views/export_dialog.h"
#include "editor/views/help_browser.h"
#include "editor/views/job_progress.h"
#include "editor/views/mapping_dialog.h"
#include "editor/views/trajectory_view.h"
#include "sdk/plugin_host.h"
#include "ui_main_window.h"

#include <QActionGroup>
#include <QCloseEvent>
#include <QComboBox>
#include <QDateTime>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QFileDialog>
#include <QFileInfo>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QInputDialog>
#include <QLabel>
#include <QMessageBox>
#include <QProgressDialog>
#include <QPushButton>
#include <QScrollArea>
#include <QSettings>
#include <QTableView>
#include <QToolButton>
#include <QTreeView>
#include <QUndoStack>
#include <QVBoxLayout>

namespace mlod {

namespace {
// The version of the dock layout saveState() writes: a layout saved by a build with another
// arrangement of docks (before the viewport became the centre) is not restored.
constexpr int kLayoutVersion = 1;
} // namespace

MainWindow::MainWindow(QWidget* parent, PluginHost* plugins)
    : QMainWindow(parent), m_ui(std::make_unique<Ui::MainWindow>()), m_document(new Document(this)),
      m_assets(new AssetTreeModel(this)), m_plugins(plugins), m_import(new ImportJob(this)),
      m_autosave(new Autosave(m_document, {}, this)) {
  m_ui->setupUi(this);
  m_ui->assetTree->setModel(m_assets);
  m_ui->menuView->addAction(m_ui->assetsDock->toggleViewAction());
  m_ui->menuView->addAction(m_ui->logDock->toggleViewAction());
  buildSummaryDock();
  m_summaryLabel->setText(tr("<h2>Motion LOD Studio</h2><p>Import a character or a motion-capture clip with "
                             "<b>File → Import…</b> (Ctrl+O), or open a project (Ctrl+Shift+O), to begin.</p>"));

  connect(m_ui->actionOpen, &QAction::triggered, this, &MainWindow::chooseFile);
  connect(m_ui->actionQuit, &QAction::triggered, this, &QWidget::close);
  connect(m_ui->actionAbout, &QAction::triggered, this, &MainWindow::showAbout);
  auto* guide = new QAction(tr("&User Guide"), this);
  guide->setObjectName("actionUserGuide");
  guide->setShortcut(QKeySequence::HelpContents);
  guide->setToolTip(tr("The user guide, with pictures"));
  connect(guide, &QAction::triggered, this, [this] {
    if (!m_help) {
      m_help = new HelpBrowser(this);
      m_help->setAttribute(Qt::WA_DeleteOnClose);
    }
    m_help->show();
    m_help->raise();
  });
  m_ui->menuHelp->insertAction(m_ui->actionAbout, guide);
  addAction(guide);
  connect(m_import, &ImportJob::finished, this, &MainWindow::onImported);
  connect(m_import, &ImportJob::failed, this, &MainWindow::onImportFailed);
  connect(m_ui->assetTree->selectionModel(), &QItemSelectionModel::currentChanged, this,
          [this](const QModelIndex& current) {
            const int row = m_assets->assetRow(current);
            if (const Asset* asset = m_assets->assetAt(row)) {
              showAsset(*asset);
              m_document->setCurrentAsset(row, std::max(0, m_assets->clipRow(current)));
            }
          });
  connect(m_ui->assetTree, &QTreeView::doubleClicked, this, [this](const QModelIndex& index) {
    const int row = m_assets->assetRow(index);
    if (!m_assets->isMissing(row))
      return;
    const QString path = QFileDialog::getOpenFileName(this, tr("Where is %1 now?").arg(m_document->assetFilePath(row)));
    if (!path.isEmpty())
      m_document->relinkAsset(row, path);
  });
  connect(m_document, &Document::assetsChanged, this, [this] {
    QStringList paths;
    for (int i = 0; i < m_document->assetCount(); ++i)
      paths << m_document->assetFilePath(i);
    std::vector<std::shared_ptr<const Asset>> assets;
    for (int i = 0; i < m_document->assetCount(); ++i)
      assets.push_back(m_document->asset(i));
    // One pass over the mappings, not one per asset: a project may hold thousands of each.
    std::vector<QStringList> parts(assets.size());
    for (const ProjectMapping& mapping : m_document->project().mappings) {
      if (mapping.motion < 0 || mapping.character < 0 ||
          std::max(mapping.motion, mapping.character) >= int(parts.size()))
        continue; // Project::validate() rules it out
      parts[std::size_t(mapping.motion)] << tr("drives %1 (%2 joint pairs)")
                                                .arg(QString::fromStdString(mapping.mapping.characterName))
                                                .arg(mapping.mapping.pairs.size());
      parts[std::size_t(mapping.character)]
          << tr("driven by %1").arg(QString::fromStdString(mapping.mapping.motionName));
    }
    QStringList notes;
    for (const QStringList& part : parts)
      notes << part.join(", ");
    m_assets->setAssets(assets, paths, notes);
    int characters = 0, motions = 0;
    for (const auto& asset : assets)
      if (asset)
        ++(asset->meshes.empty() ? motions : characters);
    m_ui->assetsDock->setWindowTitle(tr("Assets — %1, %2")
                                         .arg(countText(characters, "character", "characters"),
                                              countText(motions, "motion", "motions")));
    m_ui->assetTree->resizeColumnToContents(AssetTreeModel::NameColumn);
    if (const Asset* asset = m_document->currentAssetPtr())
      showAsset(*asset);
  });
  connect(m_document, &Document::assetsLoaded, this, [this](const QList<int>& indices) {
    for (int index : indices)
      m_assets->setAsset(index, m_document->asset(index), m_document->assetFilePath(index));
    if (const Asset* asset = m_document->currentAssetPtr())
      showAsset(*asset);
  });
  connect(m_document, &Document::message, this, &MainWindow::log);
  connect(m_document->undoStack(), &QUndoStack::indexChanged, this, [this](int index) {
    // What each step does, as the Edit menu names it: edits, undos and redos alike.
    const QUndoStack* stack = m_document->undoStack();
    if (stack->count() == 0) { // cleared (a project opened)
      m_loggedIndex = 0;
      return;
    }
    if (index > m_loggedIndex)
      log(tr("Edit: %1").arg(stack->text(index - 1)));
    else if (index < m_loggedIndex)
      log(tr("Undo: %1").arg(stack->text(index)));
    m_loggedIndex = index;
  });

  m_progress = new JobProgress(tr("Import"), tr("Cancel"), this);
  m_progress->setObjectName("importProgress");
  connect(m_progress, &QProgressDialog::canceled, this, &MainWindow::cancelImport);
  m_levelsProgress = new JobProgress(tr("LOD levels"), tr("Cancel"), this);
  m_levelsProgress->setObjectName("levelsProgress");
  connect(m_levelsProgress, &QProgressDialog::canceled, m_document->levelGenerator(), &LevelGenerator::cancel);
  connect(m_document->levelGenerator(), &LevelGenerator::progressed, m_levelsProgress,
          [this](int percent) { m_levelsProgress->step(percent, 100); }); // only while it runs: start()
  connect(m_document->levelGenerator(), &LevelGenerator::finished, this, [this](bool ok, const QString& message) {
    m_levelsProgress->finish();
    log(ok ? tr("Generated levels: %1").arg(message) : tr("Level generation: %1").arg(message));
    statusBar()->showMessage(ok ? message : tr("Level generation: %1").arg(message), 4000);
  });

  buildUnitMenu();
  buildDocks();
  buildActions();
  // Log and Summary share a tab (after the split: a dock split off a tabbed one becomes a tab).
  tabifyDockWidget(m_ui->logDock, m_summaryDock);
  m_summaryDock->raise(); // the first thing to read; the Log is one tab away
  resizeDocks({m_ui->assetsDock, m_clusteringDock}, {470, 520}, Qt::Horizontal);
  resizeDocks({m_ui->logDock}, {320}, Qt::Vertical);
  resizeDocks({m_ui->logDock, m_statisticsDock}, {360, 1240}, Qt::Horizontal);
  resizeDocks({m_ui->assetsDock, m_skeletonDock, m_levelsDock}, {160, 420, 200}, Qt::Vertical);
  buildResetLayout();
  QSettings settings;
  restoreGeometry(settings.value("mainWindow/geometry").toByteArray());
  restoreState(settings.value("mainWindow/state").toByteArray(), kLayoutVersion);
  statusBar()->showMessage(tr("Ready"));
  refreshStatus();
  refreshTitle();
}

MainWindow::~MainWindow() = default;

bool MainWindow::isImporting() const { return m_import->isRunning(); }

QProgressDialog* MainWindow::importProgress() const {
  return m_progress;
}
QProgressDialog* MainWindow::analysisProgress() const {
  return m_analysisProgress;
}
QProgressDialog* MainWindow::levelsProgress() const {
  return m_levelsProgress;
}

QString MainWindow::logText() const { return m_ui->logView->toPlainText(); }

void MainWindow::buildUnitMenu() {
  // Files without a unit of their own (BVH, X, SMD …) take this one; glTF, FBX and
  // Collada keep the unit they state unless a preset is picked here.
  QMenu* menu = m_ui->menuFile->addMenu(tr("Import &Unit"));
  menu->setToolTipsVisible(true);
  m_ui->menuFile->insertMenu(m_ui->actionQuit, menu);
  m_ui->menuFile->insertSeparator(m_ui->actionQuit);
  auto* group = new QActionGroup(this);
  const auto add = [&](const QString& text, double cmPerUnit, const QString& tooltip) {
    QAction* action = menu->addAction(text);
    action->setCheckable(true);
    action->setData(cmPerUnit);
    action->setToolTip(tooltip);
    group->addAction(action);
    return action;
  };
  add(tr("From the File"), 0.0,
      tr("glTF in metres, FBX and Collada by their stated unit; files that state none (BVH, X, OBJ …) get the preset "
         "that makes them a human height (guessed)"))
      ->setObjectName("actionUnitFromFile");
  for (const UnitPreset& preset : unitPresets())
    add(tr("%1 (%2 cm per unit)").arg(QString::fromUtf8(preset.description)).arg(preset.cmPerUnit, 0, 'g', 5),
        preset.cmPerUnit, tr("Lengths in the file are %1").arg(QString::fromUtf8(preset.description)))
        ->setObjectName(QString("actionUnit_%1").arg(preset.name));
  m_unitGroup = group; // before the saved unit is applied: it checks its action
  setImportUnitScale(QSettings().value("import/unitScale", 0.0).toDouble());
  connect(group, &QActionGroup::triggered, this, [this](QAction* action) {
    setImportUnitScale(action->data().toDouble());
    QSettings().setValue("import/unitScale", m_unitScale);
  });
}

void MainWindow::buildAssetUnitMenu(QMenu* edit) {
  // The asset in view's unit: the presets, the current one checked (none when the unit is a
  // number of its own), and Other… for any number of cm per file unit.
  m_assetUnitMenu = edit->addMenu(tr("Asset &Unit"));
  m_assetUnitMenu->setObjectName("menuAssetUnit");
  m_assetUnitMenu->setToolTipsVisible(true);
  auto* group = new QActionGroup(m_assetUnitMenu);
  for (const UnitPreset& preset : unitPresets()) {
    QAction* action = m_assetUnitMenu->addAction(
        tr("%1 (%2 cm per unit)").arg(QString::fromUtf8(preset.description)).arg(preset.cmPerUnit, 0, 'g', 5));
    action->setObjectName(QString("actionAssetUnit_%1").arg(preset.name));
    action->setCheckable(true);
    action->setData(preset.cmPerUnit);
    action->setToolTip(tr("Import the asset in view again with lengths in %1; every length and figure follows")
                           .arg(QString::fromUtf8(preset.description)));
    group->addAction(action);
    connect(action, &QAction::triggered, this, [this, action] {
      if (m_document->currentAssetPtr())
        m_document->setAssetUnitScale(m_document->currentAsset(), action->data().toDouble());
      refreshAssetUnitMenu();
    });
  }
  m_assetUnitMenu->addSeparator();
  QAction* other = m_assetUnitMenu->addAction(tr("&Other…"));
  other->setObjectName("actionAssetUnit");
  other->setToolTip(tr("Any number of cm per file unit"));
  connect(other, &QAction::triggered, this, [this] {
    const Asset* asset = m_document->currentAssetPtr();
    if (!asset)
      return;
    bool ok = false;
    const double scale = QInputDialog::getDouble(this, tr("Asset unit"), tr("cm per file unit (CMU mocap: 5.6444):"),
                                                 asset->unitScale, 1e-6, 1e6, 6, &ok);
    if (ok)
      m_document->setAssetUnitScale(m_document->currentAsset(), scale);
  });
  connect(m_assetUnitMenu, &QMenu::aboutToShow, this, &MainWindow::refreshAssetUnitMenu);
  connect(m_document, &Document::currentChanged, this, &MainWindow::refreshAssetUnitMenu);
  connect(m_document, &Document::unitScaleChanged, this, &MainWindow::refreshAssetUnitMenu);
  connect(m_document, &Document::assetsChanged, this, &MainWindow::refreshAssetUnitMenu);
  refreshAssetUnitMenu();
}

void MainWindow::refreshAssetUnitMenu() {
  const Asset* asset = m_document->currentAssetPtr();
  m_assetUnitMenu->setEnabled(asset != nullptr);
  for (QAction* action : m_assetUnitMenu->actions()) {
    if (!action->isCheckable())
      continue;
    const double preset = action->data().toDouble();
    action->setChecked(asset && std::abs(asset->unitScale - preset) <= 1e-9 * preset);
  }
}

void MainWindow::offerToRegenerateDistances() {
  // Switch distances and pixel errors are lengths measured at the old unit: stale now.
  const std::optional<double> budget = switchDistancePixelBudget(m_document->lods());
  if (!budget)
    return; // no distances yet: nothing went stale
  const double pixels = *budget;
  log(tr("The switch distances were computed at the old unit and are stale: regenerate them (Budget…)."));
  auto* box = new QMessageBox(QMessageBox::Question, tr("Switch distances are stale"),
                              tr("The LOD levels' switch distances were computed at the old unit."),
                              QMessageBox::NoButton, this);
  box->setObjectName("staleDistancesBox");
  box->setInformativeText(tr("Regenerate the levels from the same pixel budget (%1 px, %2 levels)?")
                              .arg(pixels)
                              .arg(m_document->levelCount()));
  QPushButton* regenerate = box->addButton(tr("Regenerate"), QMessageBox::AcceptRole);
  regenerate->setObjectName("regenerateButton");
  box->addButton(tr("Keep"), QMessageBox::RejectRole);
  box->setAttribute(Qt::WA_DeleteOnClose);
  const int levels = m_document->levelCount();
  connect(regenerate, &QPushButton::clicked, this, [this, pixels, levels] { generateLevels(pixels, levels); });
  box->open(); // non-modal: scripted sessions and tests are never blocked by it
}

void MainWindow::setImportUnitScale(double cmPerUnit) {
  m_unitScale = cmPerUnit > 0.0 ? cmPerUnit : 0.0;
  for (QAction* action : m_unitGroup ? m_unitGroup->actions() : QList<QAction*>{})
    action->setChecked(std::abs(action->data().toDouble() - m_unitScale) < 1e-9);
}

void MainWindow::chooseFile() {
  QSettings settings;
  const QString path = QFileDialog::getOpenFileName(
      this, tr("Import character or motion"), settings.value("import/lastDir").toString(),
      tr("Characters and motions (*.bvh *.fbx *.gltf *.glb *.dae *.x *.smd *.md5mesh *.md5anim *.ms3d *.b3d *.obj);;"
         "All files (*)"));
  if (path.isEmpty())
    return;
  settings.setValue("import/lastDir", QFileInfo(path).absolutePath());
  importFile(path);
}

void MainWindow::importFile(const QString& path) { importFileWithUnit(path, m_unitScale); }

void MainWindow::importFileWithUnit(const QString& path, double unitScale) {
  if (m_import->isRunning()) {
    log(tr("An import is already running; %1 was not started.").arg(path));
    return;
  }
  log(tr("Importing %1 …").arg(path));
  statusBar()->showMessage(tr("Importing %1 …").arg(QFileInfo(path).fileName()));
  ImportOptions options;
  options.unitScale = unitScale;
  m_pendingScale = unitScale;
  m_import->start(path, options);
  m_progress->begin(tr("Importing %1 …").arg(QFileInfo(path).fileName())); // the importer reports no fraction
}

void MainWindow::cancelImport() { m_import->cancel(); }

void MainWindow::onImported(const QString& path, std::shared_ptr<const Asset> asset) {
  m_progress->finish();
  edit::addAsset(*m_document, asset, path, m_pendingScale);
  const QModelIndex index = m_assets->index(m_assets->rowCount() - 1, 0);
  m_ui->assetTree->expand(index);
  m_ui->assetTree->setCurrentIndex(index);
  m_ui->assetTree->resizeColumnToContents(AssetTreeModel::NameColumn);
  for (const std::string& warning : asset->warnings)
    log(tr("warning: %1: %2").arg(path, QString::fromStdString(warning)));
  if (asset->unitSource == "guessed")
    log(tr("%1 states no unit: guessed %2 cm per file unit, which makes it %3 m tall (Edit → Asset Unit to change)")
            .arg(QFileInfo(path).fileName())
            .arg(asset->unitScale, 0, 'g', 5)
            .arg(standingHeightCm(*asset) / 100.0, 0, 'f', 2));
  const QString message = tr("Imported %1: %2, %3, %4")
                              .arg(QFileInfo(path).fileName(), countText(asset->skeleton.jointCount(), "joint", "joints"),
                                   countText(qsizetype(asset->clips.size()), "clip", "clips"),
                                   countText(qsizetype(asset->meshes.size()), "mesh", "meshes"));
  log(message);
  statusBar()->showMessage(message, 10000);
  showAsset(*asset);
  emit importFinished(true, path, message);
}

void MainWindow::onImportFailed(const QString& path, const QString& reason) {
  m_progress->finish();
  const QString message = tr("error: %1: %2").arg(path, reason);
  log(message);
  statusBar()->showMessage(tr("Import failed"), 10000);
  // Non-modal, so scripted sessions and tests are never blocked by it.
  auto* box = new QMessageBox(QMessageBox::Warning, tr("Import failed"),
                              tr("%1 could not be imported.").arg(QFileInfo(path).fileName()), QMessageBox::Ok, this);
  box->setInformativeText(reason);
  box->setAttribute(Qt::WA_DeleteOnClose);
  box->open();
  emit importFinished(false, path, reason);
}

void MainWindow::showAsset(const Asset& asset) {
  QString html = tr("<h2>%1</h2><p>%2 · %3 m tall · %4 cm per file unit (%5)</p>")
                     .arg(QFileInfo(QString::fromStdString(asset.sourcePath)).fileName().toHtmlEscaped(),
                          QString::fromStdString(asset.format).toHtmlEscaped())
                     .arg(standingHeightCm(asset) / 100.0, 0, 'f', 2)
                     .arg(asset.unitScale)
                     .arg(QString::fromStdString(asset.unitSource));
  html += tr("<p><b>Skeleton:</b> %1 joints, %2 leaves</p>").arg(asset.skeleton.jointCount()).arg(asset.skeleton.leafCount());
  if (asset.clips.empty())
    html += tr("<p><b>Clips:</b> none (a character without animation)</p>");
  html += "<table cellspacing=6><tr><th align=left>Clip</th><th>Frames</th><th>fps</th><th>Seconds</th><th>Rotation channels</th></tr>";
  for (const Clip& clip : asset.clips)
    html += QString("<tr><td>%1</td><td align=right>%2</td><td align=right>%3</td><td align=right>%4</td><td align=right>%5</td></tr>")
                .arg(QString::fromStdString(clip.name).toHtmlEscaped())
                .arg(clip.frameCount)
                .arg(clip.fps, 0, 'g', 6)
                .arg(clip.durationSeconds(), 0, 'f', 2)
                .arg(clip.rotationChannelCount());
  html += "</table>";
  if (asset.meshes.empty())
    html += tr("<p><b>Mesh:</b> none (a motion without a character mesh)</p>");
  else
    html += "<table cellspacing=6><tr><th align=left>Mesh</th><th>Vertices</th><th>Triangles</th><th>Bones</th></tr>";
  for (const SkinnedMesh& mesh : asset.meshes)
    html += QString("<tr><td>%1</td><td align=right>%2</td><td align=right>%3</td><td align=right>%4</td></tr>")
                .arg(QString::fromStdString(mesh.name).toHtmlEscaped())
                .arg(mesh.vertexCount())
                .arg(mesh.triangleCount())
                .arg(mesh.boneCount());
  if (!asset.meshes.empty())
    html += "</table>";
  m_summaryLabel->setText(html);
}

void MainWindow::log(const QString& line) {
  m_ui->logView->appendPlainText(QDateTime::currentDateTime().toString("hh:mm:ss  ") + line);
}

void MainWindow::showAbout() {
  QMessageBox::about(this, tr("About Motion LOD Studio"),
                     tr("<h3>Motion LOD Studio %1</h3><p>Motion level-of-detail for crowds: joint posture "
                        "clustering for the skeleton, per-segment simplification for the mesh "
                        "(after Ahn &amp; Wohn).</p>")
                         .arg(kVersion));
}

void MainWindow::closeEvent(QCloseEvent* event) {
  if (m_document->isModified()) {
    const QMessageBox::StandardButton answer = QMessageBox::question(
        this, tr("Unsaved changes"), tr("The project has unsaved changes. Save them before closing?"),
        QMessageBox::Save | QMessageBox::Discard | QMessageBox::Cancel, QMessageBox::Save);
    if (answer == QMessageBox::Cancel) {
      event->ignore();
      return;
    }
    if (answer == QMessageBox::Save) {
      m_saveAction->trigger();
      if (m_document->isModified()) { // not saved (cancelled or failed): keep the window
        event->ignore();
        return;
      }
    }
  }
  m_autosave->discard(); // a clean close leaves nothing to recover
  m_document->analysisRunner()->cancel();
  QSettings settings;
  settings.setValue("mainWindow/geometry", saveGeometry());
  settings.setValue("mainWindow/state", saveState(kLayoutVersion));
  cancelImport();
  QMainWindow::closeEvent(event);
}

// ---- docks, actions, views ----------------------------------------------------------

QDockWidget* MainWindow::addDock(const QString& name, const QString& title, QWidget* widget, Qt::DockWidgetArea area) {
  auto* dock = new QDockWidget(title, this);
  dock->setObjectName(name); // saveState() keys the layout by it
  dock->setWidget(widget);
  addDockWidget(area, dock);
  m_ui->menuView->addAction(dock->toggleViewAction());
  return dock;
}

void MainWindow::buildSummaryDock() {
  // What the asset in view holds (skeleton, clips, meshes), beside the Log.
  m_summaryLabel = new QLabel;
  m_summaryLabel->setObjectName("summaryLabel");
  m_summaryLabel->setAlignment(Qt::AlignLeading | Qt::AlignLeft | Qt::AlignTop);
  m_summaryLabel->setWordWrap(true);
  m_summaryLabel->setTextInteractionFlags(Qt::TextSelectableByMouse);
  m_summaryLabel->setMargin(8);
  auto* scroll = new QScrollArea;
  scroll->setWidgetResizable(true);
  scroll->setWidget(m_summaryLabel);
  m_summaryDock = addDock("summaryDock", tr("Summary"), scroll, Qt::BottomDockWidgetArea);
}

void MainWindow::buildResetLayout() {
  // View > Reset Layout: every dock back where a first run puts it, floating ones docked.
  const QByteArray defaultLayout = saveState(kLayoutVersion);
  auto* reset = new QAction(tr("&Reset Layout"), this);
  reset->setObjectName("actionResetLayout");
  reset->setToolTip(tr("Every dock back where a first run puts it"));
  connect(reset, &QAction::triggered, this, [this, defaultLayout] {
    for (QDockWidget* dock : findChildren<QDockWidget*>())
      dock->setFloating(false);
    restoreState(defaultLayout, kLayoutVersion);
  });
  m_ui->menuView->addSeparator();
  m_ui->menuView->addAction(reset);
}

void MainWindow::buildDocks() {
  buildSkeletonDock();
  buildLevelsDock();
  buildAnalysisDocks();
  buildViewports();
  buildStatusLabels();
  connectDocument();
}

void MainWindow::buildSkeletonDock() {
  // Skeleton: the joint tree with its delegates; multi-select edits every selected joint.
  m_jointModel = new JointTreeModel(m_document, this);
  m_skeletonView = new QTreeView;
  m_skeletonView->setObjectName("skeletonView");
  m_skeletonView->setModel(m_jointModel);
  m_skeletonView->setItemDelegate(new JointDelegate(m_skeletonView));
  m_skeletonView->setSelectionMode(QAbstractItemView::ExtendedSelection);
  m_skeletonView->setSelectionBehavior(QAbstractItemView::SelectRows);
  m_skeletonView->setEditTriggers(QAbstractItemView::DoubleClicked | QAbstractItemView::EditKeyPressed |
                                  QAbstractItemView::SelectedClicked);
  m_skeletonView->setUniformRowHeights(true);
  m_skeletonView->header()->setStretchLastSection(false);
  m_skeletonView->setToolTip(tr("Joints: α, threshold at the current level, lock and simplified %. Double-click or F2 to "
                                "edit; the edit applies to every selected joint"));
  m_jointModel->setSelectionProvider([this](int) { return selectedJoints(); });
  // Readable joint names: the figures' columns as narrow as their two-line headers and values,
  // the name column takes the rest of the dock, a deep joint indented by 10 px a level (not
  // the style's 20) so the names keep the width; a name still too long is cut in the middle
  // and its tooltip has it whole.
  m_skeletonView->setIndentation(10);
  m_skeletonView->setTextElideMode(Qt::ElideMiddle);
  QHeaderView* jointHeader = m_skeletonView->header();
  jointHeader->setMinimumSectionSize(24);
  jointHeader->setSectionResizeMode(QHeaderView::ResizeToContents);
  jointHeader->setSectionResizeMode(JointTreeModel::NameColumn, QHeaderView::Stretch);
  jointHeader->setDefaultAlignment(Qt::AlignCenter);
  connect(m_jointModel, &QAbstractItemModel::modelReset, this, [this] { m_skeletonView->expandAll(); });
  connect(m_skeletonView->selectionModel(), &QItemSelectionModel::currentChanged, this,
          [this](const QModelIndex& current) { m_document->setCurrentJoint(m_jointModel->jointAt(current)); });
  m_skeletonDock = addDock("skeletonDock", tr("Skeleton"), m_skeletonView, Qt::LeftDockWidgetArea);
}

void MainWindow::buildLevelsDock() {
  // LOD levels, with the project's alpha beside them.
  auto* levelsPanel = new QWidget;
  auto* levelsLayout = new QVBoxLayout(levelsPanel);
  levelsLayout->setContentsMargins(2, 2, 2, 2);
  m_levelsModel = new LevelsModel(m_document, this);
  m_levelsView = new QTableView;
  m_levelsView->setObjectName("levelsView");
  m_levelsView->setModel(m_levelsModel);
  m_levelsView->setItemDelegate(new LevelDelegate(m_levelsView));
  m_levelsView->setEditTriggers(QAbstractItemView::DoubleClicked | QAbstractItemView::EditKeyPressed |
                                QAbstractItemView::SelectedClicked);
  connect(m_levelsModel, &LevelsModel::editRefused, this, [this](const QString& reason) { log(reason); });
  m_levelsView->setSelectionBehavior(QAbstractItemView::SelectRows);
  m_levelsView->setSelectionMode(QAbstractItemView::SingleSelection);
  m_levelsView->horizontalHeader()->setStretchLastSection(true);
  m_levelsView->verticalHeader()->hide();
  // rows as tall as the text (the style's 30 px took the Skeleton dock's room)
  m_levelsView->verticalHeader()->setMinimumSectionSize(m_levelsView->fontMetrics().height() + 6);
  m_levelsView->verticalHeader()->setDefaultSectionSize(m_levelsView->fontMetrics().height() + 6);
  m_levelsView->horizontalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
  connect(m_levelsView->selectionModel(), &QItemSelectionModel::currentRowChanged, this,
          [this](const QModelIndex& current) {
            if (current.isValid())
              m_document->setCurrentLevel(current.row());
          });
  levelsLayout->addWidget(m_levelsView);
  // Every level in sight: the table asks for the height of all its rows (up to 12).
  const auto fitLevels = [this] {
    const int rows = std::min(12, m_levelsModel->rowCount());
    m_levelsView->setMinimumHeight(m_levelsView->horizontalHeader()->sizeHint().height() +
                                   rows * m_levelsView->verticalHeader()->defaultSectionSize() +
                                   2 * m_levelsView->frameWidth() + 2);
  };
  connect(m_levelsModel, &QAbstractItemModel::modelReset, this, fitLevels);
  connect(m_levelsModel, &QAbstractItemModel::rowsInserted, this, fitLevels);
  connect(m_levelsModel, &QAbstractItemModel::rowsRemoved, this, fitLevels);
  fitLevels();
  auto* buttons = new QHBoxLayout;
  const auto button = [&](const QString& name, const QString& text, const QString& tip) {
    auto* b = new QToolButton;
    b->setObjectName(name);
    b->setText(text);
    b->setToolTip(tip);
    buttons->addWidget(b);
    return b;
  };
  connect(button("addLevelButton", tr("+"), tr("Add a level (twice the last threshold) — Ctrl+Shift+L")), &QToolButton::clicked,
          this, [this] { m_addLevelAction->trigger(); }); // (the actions: buildActions(), right after)
  connect(button("removeLevelButton", tr("−"), tr("Remove the current level")), &QToolButton::clicked, this,
          [this] { edit::removeLevel(*m_document, m_document->currentLevel()); });
  connect(button("levelUpButton", tr("↑"), tr("Move the current level up")), &QToolButton::clicked, this, [this] {
    const int level = m_document->currentLevel();
    edit::moveLevel(*m_document, level, level - 1);
  });
  connect(button("levelDownButton", tr("↓"), tr("Move the current level down")), &QToolButton::clicked, this, [this] {
    const int level = m_document->currentLevel();
    edit::moveLevel(*m_document, level, level + 1);
  });
  connect(button("generateLevelsButton", tr("Budget…"),
                 tr("Generate the levels from an error budget in pixels on screen — Ctrl+Shift+G")),
          &QToolButton::clicked, this, [this] { m_generateLevelsAction->trigger(); });
  buttons->addStretch();
  buttons->addWidget(new QLabel(tr("α")));
  m_alphaBox = new QDoubleSpinBox;
  m_alphaBox->setObjectName("alphaBox");
  m_alphaBox->setRange(0.0, 1000.0);
  m_alphaBox->setDecimals(2);
  m_alphaBox->setSingleStep(0.5);
  m_alphaBox->setSuffix(tr(" cm"));
  m_alphaBox->setValue(m_document->project().alpha);
  m_alphaBox->setToolTip(
      tr("Orientation weight α of every joint without its own, cm (default %1)").arg(kDefaultJpcAlpha));
  connect(m_alphaBox, &QDoubleSpinBox::valueChanged, this, [this](double value) { edit::setAlpha(*m_document, value); });
  buttons->addWidget(m_alphaBox);
  m_modeBox = new QComboBox;
  m_modeBox->setObjectName("modeBox");
  m_modeBox->addItem(tr("Greedy"), int(JpcMode::Greedy));
  m_modeBox->addItem(tr("Optimal"), int(JpcMode::Optimal));
  m_modeBox->setToolTip(tr("Greedy: the paper's longest-range-first clusters. Optimal: under the same error bound, the "
                           "clusters that cover the most frames"));
  connect(m_modeBox, &QComboBox::currentIndexChanged, this,
          [this](int index) { edit::setMode(*m_document, JpcMode(m_modeBox->itemData(index).toInt())); });
  buttons->addWidget(m_modeBox);
  levelsLayout->addLayout(buttons);
  m_levelsDock = addDock("levelsDock", tr("LOD Levels"), levelsPanel, Qt::LeftDockWidgetArea);
}

// The clustering table, the trajectory and the statistics of the current joint.
void MainWindow::buildAnalysisDocks() {
  m_clusteringView = new ClusteringTableView;
  m_clusteringView->setObjectName("clusteringView");
  m_clusteringDock = addDock("clusteringDock", tr("Clustering Table"), m_clusteringView, Qt::RightDockWidgetArea);
  connect(m_clusteringView, &ClusteringTableView::hovered, this, [this](int t, int ref, double error) {
    m_frameLabel->setText(tr("frame %1 · t_ref %2 · E %3 cm·°").arg(t).arg(ref).arg(error, 0, 'f', 2));
  });
  m_trajectoryView = new TrajectoryView;
  m_trajectoryView->setObjectName("trajectoryView");
  m_trajectoryDock = addDock("trajectoryDock", tr("Trajectory"), m_trajectoryView, Qt::RightDockWidgetArea);
  splitDockWidget(m_clusteringDock, m_trajectoryDock, Qt::Vertical);
  m_statisticsView = new StatisticsView;
  m_statisticsView->setObjectName("statisticsView");
  m_statisticsDock = addDock("statisticsDock", tr("Statistics"), m_statisticsView, Qt::BottomDockWidgetArea);
  splitDockWidget(m_ui->logDock, m_statisticsDock, Qt::Horizontal);
}

void MainWindow::buildViewports() {
  // The 3D views (viewport/): the character, original and simplified, and the crowd; one
  // timeline drives both.
  auto* viewport = new ViewportPanel(m_document);
  viewport->setObjectName("viewportPanel");
  m_viewportPanel = viewport;
  // The character view is the window's centre; the Crowd dock shares the right-hand column
  // with the Trajectory, so raising it shows the crowd and the character together.
  setCentralWidget(viewport);
  m_crowdPanel = new CrowdPanel(m_document, viewport->playback());
  m_crowdPanel->setObjectName("crowdPanel");
  connect(viewport, &ViewportPanel::mappingChosen, m_crowdPanel, &CrowdPanel::setMapping);
  m_ui->menuView->insertAction(m_ui->menuView->actions().value(0), viewport->wireframeAction());
  m_ui->menuView->insertSeparator(m_ui->menuView->actions().value(1));
  m_ui->menuView->setToolTipsVisible(true);
  m_crowdDock = addDock("crowdDock", tr("Crowd"), m_crowdPanel, Qt::RightDockWidgetArea);
  tabifyDockWidget(m_trajectoryDock, m_crowdDock);
  m_trajectoryDock->raise();
  connect(viewport->playback(), &Playback::timeChanged, m_statisticsView,
          [this, viewport] { m_statisticsView->setPlayhead(viewport->playback()->frame()); });
  auto* currentFrame = new QLabel(viewport->timeline()->frameText());
  currentFrame->setObjectName("currentFrameLabel");
  currentFrame->setToolTip(tr("The current frame of the 3D views (the Viewport's timeline)"));
  connect(viewport->playback(), &Playback::timeChanged, currentFrame,
          [currentFrame, viewport] { currentFrame->setText(viewport->timeline()->frameText()); });
  statusBar()->addPermanentWidget(currentFrame);
}

void MainWindow::buildStatusLabels() {
  m_clipLabel = new QLabel;
  m_frameLabel = new QLabel;
  m_levelLabel = new QLabel;
  m_jointLabel = new QLabel;
  m_clipLabel->setToolTip(tr("The clip in view"));
  m_frameLabel->setToolTip(tr("The table entry under the cursor"));
  m_levelLabel->setToolTip(tr("The LOD level every view shows (PgUp / PgDown)"));
  m_jointLabel->setToolTip(tr("The selected joint at the current level: threshold (cm·degrees), simplified %, clusters, max E"));
  for (QLabel* label : {m_clipLabel, m_frameLabel, m_levelLabel, m_jointLabel})
    statusBar()->addPermanentWidget(label);
}

// The views follow the document: its current joint and level, settings and analysis.
void MainWindow::connectDocument() {
  connect(m_document, &Document::currentChanged, this, &MainWindow::refreshViews);
  connect(m_document, &Document::settingsChanged, this, [this] {
    const QSignalBlocker block(m_alphaBox);
    m_alphaBox->setValue(m_document->project().alpha);
    const QSignalBlocker blockMode(m_modeBox);
    m_modeBox->setCurrentIndex(m_modeBox->findData(int(m_document->project().mode)));
    refreshStatus();
  });
  connect(m_document, &Document::analysisFinished, this, [this](bool ok, const QString& message) {
    m_analysisProgress->finish();
    if (ok && m_document->currentJoint() < 0)
      selectDefaultJoint();
    refreshViews();
    if (ok && m_document->analysis())
      statusBar()->showMessage(message, 4000);
  });
  m_analysisProgress = new JobProgress(tr("Clustering"), tr("Cancel"), this);
  m_analysisProgress->setObjectName("analysisProgress");
  connect(m_analysisProgress, &QProgressDialog::canceled, m_document->analysisRunner(), &AnalysisRunner::cancel);
  connect(m_document, &Document::analysisStarted, this,
          [this] { m_analysisProgress->begin(tr("Clustering joints …"), 100); });
  connect(m_document, &Document::analysisProgress, this, [this](int done, int total) {
    if (m_document->isAnalysing())
      m_analysisProgress->step(done, total);
  });
  connect(m_document->undoStack(), &QUndoStack::cleanChanged, this, &MainWindow::refreshTitle);
}

void MainWindow::buildActions() {
  QUndoStack* stack = m_document->undoStack();
  QAction* undo = stack->createUndoAction(this, tr("&Undo"));
  undo->setObjectName("actionUndo");
  undo->setShortcut(QKeySequence::Undo);
  QAction* redo = stack->createRedoAction(this, tr("&Redo"));
  redo->setObjectName("actionRedo");
  // The platform's redo keys (Ctrl+Y on some, Ctrl+Shift+Z on others), and Ctrl+Shift+Z on all.
  QList<QKeySequence> redoKeys = QKeySequence::keyBindings(QKeySequence::Redo);
  if (!redoKeys.contains(QKeySequence("Ctrl+Shift+Z")))
    redoKeys.append(QKeySequence("Ctrl+Shift+Z"));
  redo->setShortcuts(redoKeys);
  QMenu* edit = new QMenu(tr("&Edit"), this);
  menuBar()->insertMenu(m_ui->menuView->menuAction(), edit);
  edit->addAction(undo);
  edit->addAction(redo);
  edit->addSeparator();
  const auto action = [&](QMenu* menu, const QString& name, const QString& text, const QKeySequence& key,
                          const QString& tip, auto&& slot) {
    auto* a = new QAction(text, this);
    a->setObjectName(name);
    a->setShortcut(key);
    a->setToolTip(tip);
    a->setStatusTip(tip);
    connect(a, &QAction::triggered, this, slot);
    menu->addAction(a);
    addAction(a); // shortcuts work wherever the focus is
    return a;
  };
  action(edit, "actionLockJoints", tr("&Lock / Unlock Selected Joints"), QKeySequence("Ctrl+L"),
         tr("Locked joints are never simplified"), [this] {
           const std::vector<int> joints = selectedJoints();
           if (joints.empty())
             return;
           const auto& settings = m_document->project().assets[std::size_t(m_document->currentAsset())].joints;
           const auto found = settings.find(m_document->currentAssetPtr()->skeleton.joints[std::size_t(joints[0])].name);
           edit::setJointsLocked(*m_document, joints, !(found != settings.end() && found->second.locked));
         });
  action(edit, "actionApplyToChildren", tr("Apply to &Children"), QKeySequence("Ctrl+Shift+C"),
         tr("Copy the current joint's α, thresholds and lock to all its descendants"),
         [this] { edit::applyToChildren(*m_document, m_document->currentJoint()); });
  action(edit, "actionClearJointThreshold", tr("Use the Level's &Threshold"), QKeySequence("Ctrl+Backspace"),
         tr("Remove the selected joints' own threshold at the current level"),
         [this] { edit::setJointThreshold(*m_document, selectedJoints(), m_document->currentLevel(), std::nullopt); });
  action(edit, "actionRemoveAsset", tr("Remove &Asset"), QKeySequence(), tr("Remove the asset in view from the project"),
         [this] { edit::removeAsset(*m_document, m_document->currentAsset()); });
  action(edit, "actionAssignMotion", tr("Assign &Motion to Character…"), QKeySequence("Ctrl+Shift+M"),
         tr("Play the motion in view on a character: joints matched by name (rig conventions), rest-pose differences "
            "computed (the paper's section 3.1)"),
         [this] {
           const int motion = m_document->currentAsset();
           QStringList names;
           std::vector<int> characters;
           for (int i = 0; i < m_document->assetCount(); ++i)
             if (i != motion && m_document->asset(i) && !m_document->asset(i)->meshes.empty()) {
               characters.push_back(i);
               names << QFileInfo(m_document->assetFilePath(i)).fileName();
             }
           if (characters.empty()) {
             showError(tr("No character"), tr("Import a character (a skinned mesh) first."),
                       tr("assign motion: the project has no character"));
             return;
           }
           int chosen = characters.front();
           if (characters.size() > 1) {
             bool ok = false;
             const QString name = QInputDialog::getItem(this, tr("Assign motion"), tr("Character:"), names, 0, false, &ok);
             if (!ok)
               return;
             chosen = characters[std::size_t(names.indexOf(name))];
           }
           QString error, warning;
           if (!edit::assignMotion(*m_document, motion, chosen, &error, &warning)) {
             showError(tr("Cannot assign the motion"), tr("The motion was not assigned."), error);
             return;
           }
           log(m_document->undoStack()->text(m_document->undoStack()->index() - 1));
           if (!warning.isEmpty())
             showWarning(tr("The motion hardly fits the character"),
                         tr("The automatic joint mapping drives little of the character: it may stand or move "
                            "unlike the motion. Check it in Edit > Edit Joint Mapping… (Ctrl+Alt+M), or undo."),
                         warning);
         });
  m_generateLevelsAction = action(edit, "actionGenerateLevels", tr("&Generate Levels from Pixel Budget…"), QKeySequence("Ctrl+Shift+G"),
         tr("Compute every level's threshold, mesh ratio and switch distance so that each stays within N pixels on "
            "screen (motion and mesh together, in the background)"),
         [this] { openBudgetDialog(); });
  action(edit, "actionEditMapping", tr("Edit Joint &Mapping…"), QKeySequence("Ctrl+Alt+M"),
         tr("Edit which motion joint drives each character joint, for the asset in view (motion or character)"),
         [this] { editMapping(); });
  buildAssetUnitMenu(edit);
  connect(m_document, &Document::unitScaleChanged, this, [this](bool ok, const QString& text) {
    log(text);
    if (ok)
      offerToRegenerateDistances();
  });
  edit->addSeparator();
  m_addLevelAction = action(edit, "actionAddLevel", tr("&Add Level"), QKeySequence("Ctrl+Shift+L"),
         tr("Add a LOD level with twice the last threshold (cm·degrees)"),
         [this] { edit::addLevel(*m_document, nextLodLevelThreshold(m_document->lods())); });
  action(edit, "actionRemoveLevel", tr("&Remove Current Level"), QKeySequence(), tr("Remove the current LOD level"),
         [this] { edit::removeLevel(*m_document, m_document->currentLevel()); });
  action(edit, "actionNextLevel", tr("&Next Level"), QKeySequence(Qt::Key_PageDown), tr("Show the next LOD level"),
         [this] { m_document->setCurrentLevel(m_document->currentLevel() + 1); });
  action(edit, "actionPreviousLevel", tr("&Previous Level"), QKeySequence(Qt::Key_PageUp), tr("Show the previous LOD level"),
         [this] { m_document->setCurrentLevel(m_document->currentLevel() - 1); });

  // Projects, in the File menu above Import.
  QMenu* file = m_ui->menuFile;
  QAction* first = file->actions().value(0);
  const auto fileAction = [&](const QString& name, const QString& text, const QKeySequence& key, const QString& tip,
                              auto&& slot) {
    auto* a = new QAction(text, this);
    a->setObjectName(name);
    a->setShortcut(key);
    a->setToolTip(tip);
    connect(a, &QAction::triggered, this, slot);
    file->insertAction(first, a);
    return a;
  };
  fileAction("actionNewProject", tr("&New Project"), QKeySequence::New,
             tr("Start an empty, untitled project (asks first when this one has unsaved changes)"),
             [this] { newProject(); });
  fileAction("actionOpenProject", tr("&Open Project…"), QKeySequence("Ctrl+Shift+O"),
             tr("Open a Motion LOD project (%1)").arg(kProjectSuffix), [this] {
               const QString path = QFileDialog::getOpenFileName(this, tr("Open project"),
                                                                 QSettings().value("project/lastDir").toString(),
                                                                 tr("Motion LOD projects (*%1)").arg(kProjectSuffix));
               if (!path.isEmpty())
                 openProject(path);
             });
  m_recentMenu = new QMenu(tr("Recent &Projects"), this);
  m_recentMenu->setObjectName("menuRecent");
  file->insertMenu(first, m_recentMenu);
  const auto saveAs = [this] {
    const QString path =
        QFileDialog::getSaveFileName(this, tr("Save project"), QSettings().value("project/lastDir").toString(),
                                     tr("Motion LOD projects (*%1)").arg(kProjectSuffix));
    if (!path.isEmpty())
      saveProject(isProjectFile(path.toStdString()) ? path : path + kProjectSuffix);
  };
  m_saveAction = fileAction("actionSave", tr("&Save Project"), QKeySequence::Save, tr("Save the project (atomically)"), [this, saveAs] {
    if (m_document->fileName().isEmpty())
      saveAs();
    else
      saveProject(m_document->fileName());
  });
  fileAction("actionSaveAs", tr("Save Project &As…"), QKeySequence::SaveAs, tr("Save the project under a new name"), saveAs);
  fileAction("actionExport", tr("&Export…"), QKeySequence("Ctrl+E"),
             tr("Export the character's LOD set through an exporter plugin (glTF, runtime bundle, report)"), [this] {
               auto* dialog = new ExportDialog(m_document, pluginHost(), this);
               dialog->setAttribute(Qt::WA_DeleteOnClose);
               connect(dialog, &ExportDialog::exportFinished, this, [this](bool ok, const QString& message) {
                 log(ok ? tr("Exported: %1").arg(message) : tr("Export failed: %1").arg(message));
               });
               dialog->open();
             });
  file->insertSeparator(first);
  refreshRecentMenu();
}

PluginHost* MainWindow::pluginHost() {
  if (!m_plugins) {
    m_ownPlugins = std::make_unique<PluginHost>();
    m_ownPlugins->loadDefault();
    m_plugins = m_ownPlugins.get();
  }
  return m_plugins;
}

void MainWindow::showDock(QDockWidget* dock) {
  dock->raise();
  resizeDocks({dock}, {620}, Qt::Vertical);
}

std::vector<int> MainWindow::selectedJoints() const {
  std::vector<int> joints;
  for (const QModelIndex& index : m_skeletonView->selectionModel()->selectedRows())
    joints.push_back(m_jointModel->jointAt(index));
  if (joints.empty() && m_document->currentJoint() >= 0)
    joints.push_back(m_document->currentJoint());
  std::sort(joints.begin(), joints.end());
  return joints;
}

void MainWindow::selectDefaultJoint() {
  // So that the clustering table and the trajectory show something as soon as a clip
  // opens: the joint with a child (a direction) and the most clusters at the level in view.
  const auto analysis = m_document->analysis();
  const Asset* asset = m_document->currentAssetPtr();
  const int level = m_document->currentLevel();
  if (!analysis || !asset || level < 0 || level >= analysis->levelCount())
    return;
  const std::vector<JointMetrics>& joints = analysis->levels[std::size_t(level)].joints;
  int best = -1;
  for (int j = 0; j < int(joints.size()) && j < asset->skeleton.jointCount(); ++j)
    if (joints[std::size_t(j)].clusterable && !asset->skeleton.children(j).empty() &&
        (best < 0 || joints[std::size_t(j)].clusters > joints[std::size_t(best)].clusters))
      best = j;
  if (best >= 0)
    m_document->setCurrentJoint(best);
}

void MainWindow::refreshViews() {
  const auto analysis = m_document->analysis();
  const int joint = m_document->currentJoint();
  const int level = m_document->currentLevel();
  m_clusteringView->setAnalysis(analysis, joint, level);
  m_trajectoryView->setAnalysis(analysis, joint, level);
  QStringList names;
  for (const LodLevel& lod : m_document->lods().levels)
    names << QString::fromStdString(lod.name);
  m_statisticsView->setAnalysis(analysis, level, names);
  // whose set the levels are: the asset's, or the character the motion is viewed on
  const QString owner = m_document->lodSetOwnerName();
  m_levelsDock->setWindowTitle(owner.isEmpty() ? tr("LOD Levels") : tr("LOD Levels — %1").arg(owner));
  const QModelIndex row = m_levelsModel->index(level, 0);
  if (m_levelsView->currentIndex().row() != level) {
    const QSignalBlocker block(m_levelsView->selectionModel());
    m_levelsView->setCurrentIndex(row);
  }
  const QModelIndex jointIndex = m_jointModel->indexOfJoint(joint);
  if (jointIndex.isValid() && m_skeletonView->currentIndex() != jointIndex &&
      m_jointModel->jointAt(m_skeletonView->currentIndex()) != joint)
    m_skeletonView->setCurrentIndex(jointIndex);
  refreshStatus();
}

bool MainWindow::generateLevels(double pixels, int levels) {
  QString error;
  if (!m_document->levelGenerator()->start(pixels, levels, &error)) {
    showError(tr("Cannot generate levels"), tr("The levels were not generated."), error);
    return false;
  }
  m_levelsProgress->begin(tr("Generating levels (motion and mesh) …"), 100);
  return true;
}

BudgetDialog* MainWindow::openBudgetDialog() {
  if (!m_document->currentAssetPtr()) {
    showError(tr("Cannot generate levels"), tr("The levels were not generated."), tr("no asset in view"));
    return nullptr;
  }
  const LodSet& lods = m_document->lods();
  BudgetRequest initial;
  initial.levels = std::max(2, m_document->levelCount());
  initial.projection = lods.projection;
  initial.skinning = lods.skinning;
  if (const std::optional<double> made = switchDistancePixelBudget(lods)) // the budget the levels were made with
    initial.pixels = *made;
  initial.character = m_document->lodSetOwnerName(); // generation lands in that one's set
  auto* dialog = new BudgetDialog(m_document->levelGenerator(), initial, this);
  dialog->setAttribute(Qt::WA_DeleteOnClose);
  dialog->open();
  // Beside the character, not over it: centred on the window it hid the whole viewport.
  if (m_viewportPanel)
    moveBeside(dialog, m_viewportPanel->sceneView() ? static_cast<QWidget*>(m_viewportPanel->sceneView())
                                                    : static_cast<QWidget*>(m_viewportPanel));
  return dialog;
}

MappingDialog* MainWindow::editMapping() {
  const int asset = m_document->currentAsset();
  const auto& mappings = m_document->project().mappings;
  // the mapping in view (the motion on the character it is viewed on), else the first naming the asset
  int found = -1;
  for (std::size_t m = 0; m < mappings.size() && found < 0; ++m)
    if (mappings[m].motion == asset && mappings[m].character == m_document->viewedCharacter())
      found = static_cast<int>(m);
  for (std::size_t m = 0; m < mappings.size() && found < 0; ++m)
    if (mappings[m].motion == asset || mappings[m].character == asset)
      found = static_cast<int>(m);
  if (found < 0) {
    showError(tr("No joint mapping"), tr("Assign the motion in view to a character first (Ctrl+Shift+M)."),
              tr("edit mapping: the asset in view has no mapping"));
    return nullptr;
  }
  if (m_mappingDialog)
    m_mappingDialog->close();
  m_mappingDialog = new MappingDialog(m_document, found, this);
  m_mappingDialog->setAttribute(Qt::WA_DeleteOnClose);
  m_mappingDialog->show();
  return m_mappingDialog;
}

QString MainWindow::statusText() const {
  return QStringList{m_clipLabel->text(), m_levelLabel->text(), m_jointLabel->text()}.join(" | ");
}

void MainWindow::refreshStatus() {
  const Clip* clip = m_document->currentClipPtr();
  m_clipLabel->setText(clip ? tr("%1 · %2 frames at %3 fps").arg(QString::fromStdString(clip->name)).arg(clip->frameCount).arg(clip->fps)
                            : tr("no clip"));
  const int level = m_document->currentLevel();
  const LodLevel& shown = m_document->lods().levels[std::size_t(level)];
  m_levelLabel->setText(level == 0 ? tr("L0 %1 · original").arg(QString::fromStdString(shown.name))
                                   : tr("L%1 %2 · E = %3 cm·°").arg(level).arg(QString::fromStdString(shown.name)).arg(shown.motionThreshold));
  const auto analysis = m_document->analysis();
  const int joint = m_document->currentJoint();
  if (analysis && joint >= 0 && joint < analysis->prepared->jointCount() && level < analysis->levelCount()) {
    const JointMetrics& m = analysis->levels[std::size_t(level)].joints[std::size_t(joint)];
    m_jointLabel->setText(m.clusterable ? tr("%1: T %2 cm·°, %3% simplified, %4 clusters, max E %5 cm·°%6")
                                              .arg(QString::fromStdString(analysis->prepared->jointName(joint)))
                                              .arg(m.threshold)
                                              .arg(m.simplifiedPercent, 0, 'f', 1)
                                              .arg(m.clusters)
                                              .arg(m.maxError, 0, 'f', 2)
                                              .arg(m.locked ? tr(" (locked)") : QString())
                                        : tr("%1: no rotation channel").arg(QString::fromStdString(analysis->prepared->jointName(joint))));
  } else {
    m_jointLabel->setText(tr("no joint selected"));
  }
}

void MainWindow::refreshTitle() {
  const QString name = m_document->fileName().isEmpty() ? tr("Untitled") : QFileInfo(m_document->fileName()).fileName();
  setWindowTitle(tr("%1[*] — Motion LOD Studio").arg(name));
  setWindowModified(m_document->isModified());
}

void MainWindow::refreshRecentMenu() {
  m_recentMenu->clear();
  const QStringList recent = QSettings().value("project/recent").toStringList();
  for (const QString& path : recent)
    m_recentMenu->addAction(QFileInfo(path).fileName(), this, [this, path] { openProject(path); })->setToolTip(path);
  m_recentMenu->setEnabled(!recent.isEmpty());
}

void MainWindow::addRecent(const QString& path) {
  QSettings settings;
  QStringList recent = settings.value("project/recent").toStringList();
  recent.removeAll(path);
  recent.prepend(path);
  while (recent.size() > 8)
    recent.removeLast();
  settings.setValue("project/recent", recent);
  settings.setValue("project/lastDir", QFileInfo(path).absolutePath());
  refreshRecentMenu();
}

void MainWindow::showWarning(const QString& title, const QString& text, const QString& detail) {
  log(tr("warning: %1").arg(detail));
  statusBar()->showMessage(tr("Warning: %1").arg(detail), 10000);
  auto* box = new QMessageBox(QMessageBox::Warning, title, text, QMessageBox::Ok, this);
  box->setObjectName("warningBox");
  box->setInformativeText(detail);
  box->setAttribute(Qt::WA_DeleteOnClose);
  box->open(); // non-modal, as showError()'s
}

void MainWindow::showError(const QString& title, const QString& text, const QString& detail) {
  log(tr("error: %1").arg(detail));
  // Non-modal, so scripted sessions and tests are never blocked by it.
  auto* box = new QMessageBox(QMessageBox::Warning, title, text, QMessageBox::Ok, this);
  box->setObjectName("errorBox");
  box->setInformativeText(detail);
  box->setAttribute(Qt::WA_DeleteOnClose);
  box->open();
}

bool MainWindow::newProject() {
  if (m_document->isModified() && mayAsk() &&
      QMessageBox::question(this, tr("Unsaved changes"),
                            tr("A new project discards the unsaved changes of this one. Start a new project anyway?")) !=
          QMessageBox::Yes)
    return false;
  m_document->newProject();
  log(tr("New project"));
  refreshTitle();
  return true;
}

bool MainWindow::openProject(const QString& path) {
  // A file that would be refused is refused first; only a good one asks about unsaved changes.
  const std::string file = QFileInfo(path).absoluteFilePath().toStdString();
  ProjectFileOptions options{.allowOutsideAssets = true}; // asked below
  const Result<Project> probe = loadProjectFile(file, options);
  const Error outside = probe ? checkAssetPaths(*probe, file) : Error(probe.message());
  if (!probe || outside) {
    // Files outside the project's folder are read only when the user says so, seeing which
    // (the CLI's --allow-outside-assets); a hidden window or a scripted run never asks.
    const bool allowed =
        probe && mayAsk() &&
        QMessageBox::question(this, tr("Assets outside the project's folder"),
                              tr("%1 reads files outside its folder:\n\n%2\n\nOpen it anyway?")
                                  .arg(QFileInfo(path).fileName(), QString::fromStdString(outside.message())),
                              QMessageBox::Open | QMessageBox::Cancel, QMessageBox::Cancel) == QMessageBox::Open;
    if (!allowed) {
      showError(tr("Cannot open project"),
                tr("%1 was not opened; nothing was changed.").arg(QFileInfo(path).fileName()),
                tr("%1: %2").arg(path, QString::fromStdString(outside.message())));
      return false;
    }
  } else {
    options.allowOutsideAssets = false;
  }
  if (m_document->isModified() && mayAsk() &&
      QMessageBox::question(this, tr("Unsaved changes"),
                            tr("Opening %1 discards the unsaved changes of this project. Open it anyway?")
                                .arg(QFileInfo(path).fileName())) != QMessageBox::Yes)
    return false;
  QString error;
  if (!m_document->open(path, options, &error)) {
    showError(tr("Cannot open project"), tr("%1 was not opened; nothing was changed.").arg(QFileInfo(path).fileName()),
              tr("%1: %2").arg(path, error));
    return false;
  }
  log(tr("Opened project %1").arg(path));
  addRecent(QFileInfo(path).absoluteFilePath());
  refreshTitle();
  return true;
}

bool MainWindow::saveProject(const QString& path) {
  QString error;
  if (!m_document->save(path, &error)) {
    showError(tr("Cannot save project"), tr("The project was not saved; the file on disk is as it was."),
              tr("%1: %2").arg(path, error));
    return false;
  }
  m_autosave->discard();
  log(tr("Saved project %1").arg(path));
  addRecent(QFileInfo(path).absoluteFilePath());
  refreshTitle();
  return true;
}

bool MainWindow::offerRecovery(bool ask) {
  if (!m_autosave->hasRecovery())
    return false;
  if (ask && QMessageBox::question(this, tr("Recover unsaved work?"),
                                   tr("The last session ended without saving. Recover its project from the autosave?")) !=
                 QMessageBox::Yes) {
    m_autosave->discard();
    return false;
  }
  QString error;
  if (!m_document->recover(m_autosave->path(), &error)) {
    showError(tr("Cannot recover"), tr("The autosave could not be read; it was kept at %1.").arg(m_autosave->path()), error);
    return false;
  }
  log(tr("Recovered the project from %1").arg(m_autosave->path()));
  refreshTitle();
  return true;
}

} // namespace mlod
