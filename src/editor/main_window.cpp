#include "editor/main_window.h"

#include "core/version.h"
#include "editor/import_job.h"
#include "editor/models/asset_tree.h"
#include "ui_main_window.h"

#include <QActionGroup>
#include <QCloseEvent>
#include <QDateTime>
#include <QDockWidget>
#include <QFileDialog>
#include <QFileInfo>
#include <QMessageBox>
#include <QProgressDialog>
#include <QSettings>

namespace mlod {

MainWindow::MainWindow(QWidget* parent)
    : QMainWindow(parent), m_ui(std::make_unique<Ui::MainWindow>()), m_assets(new AssetTreeModel(this)),
      m_import(new ImportJob(this)) {
  m_ui->setupUi(this);
  m_ui->assetTree->setModel(m_assets);
  m_ui->menuView->addAction(m_ui->assetsDock->toggleViewAction());
  m_ui->menuView->addAction(m_ui->logDock->toggleViewAction());
  m_ui->summaryLabel->setText(tr("<h2>Motion LOD Studio</h2><p>Import a character or a motion-capture clip with "
                                 "<b>File → Import…</b> (Ctrl+O) to begin.</p>"));

  connect(m_ui->actionOpen, &QAction::triggered, this, &MainWindow::chooseFile);
  connect(m_ui->actionQuit, &QAction::triggered, this, &QWidget::close);
  connect(m_ui->actionAbout, &QAction::triggered, this, &MainWindow::showAbout);
  connect(m_import, &ImportJob::finished, this, &MainWindow::onImported);
  connect(m_import, &ImportJob::failed, this, &MainWindow::onImportFailed);
  connect(m_ui->assetTree->selectionModel(), &QItemSelectionModel::currentChanged, this,
          [this](const QModelIndex& current) {
            QModelIndex top = current;
            while (top.parent().isValid())
              top = top.parent();
            if (const Asset* asset = m_assets->assetAt(top.row()))
              showAsset(*asset);
          });

  buildUnitMenu();
  resizeDocks({m_ui->assetsDock}, {340}, Qt::Horizontal);
  resizeDocks({m_ui->logDock}, {160}, Qt::Vertical);
  QSettings settings;
  restoreGeometry(settings.value("mainWindow/geometry").toByteArray());
  restoreState(settings.value("mainWindow/state").toByteArray());
  statusBar()->showMessage(tr("Ready"));
}

MainWindow::~MainWindow() = default;

bool MainWindow::isImporting() const { return m_import->isRunning(); }

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
  add(tr("From the File"), 0.0, tr("glTF in metres, FBX and Collada by their stated unit, others 1 cm per unit"))
      ->setObjectName("actionUnitFromFile");
  for (const UnitPreset& preset : unitPresets())
    add(tr("%1 (%2 cm per unit)").arg(QString::fromUtf8(preset.description)).arg(preset.cmPerUnit, 0, 'g', 5),
        preset.cmPerUnit, tr("Lengths in the file are %1").arg(QString::fromUtf8(preset.description)))
        ->setObjectName(QString("actionUnit_%1").arg(preset.name));
  const double saved = QSettings().value("import/unitScale", 0.0).toDouble();
  setImportUnitScale(saved);
  connect(group, &QActionGroup::triggered, this, [this](QAction* action) {
    setImportUnitScale(action->data().toDouble());
    QSettings().setValue("import/unitScale", m_unitScale);
  });
  m_unitGroup = group;
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
  m_import->start(path, options);
  if (!m_progress) {
    m_progress = new QProgressDialog(this);
    m_progress->setWindowTitle(tr("Import"));
    m_progress->setRange(0, 0); // the importer reports no fraction; a busy bar, with cancel
    m_progress->setMinimumDuration(400);
    m_progress->setAutoClose(false);
    m_progress->setAutoReset(false);
    connect(m_progress, &QProgressDialog::canceled, this, &MainWindow::cancelImport);
  }
  m_progress->setLabelText(tr("Importing %1 …").arg(QFileInfo(path).fileName()));
  m_progress->reset();
  m_progress->setRange(0, 0);
  m_progress->setValue(0);
}

void MainWindow::cancelImport() { m_import->cancel(); }

void MainWindow::onImported(const QString& path, std::shared_ptr<const Asset> asset) {
  if (m_progress)
    m_progress->reset();
  const QModelIndex index = m_assets->addAsset(asset);
  m_ui->assetTree->expand(index);
  m_ui->assetTree->setCurrentIndex(index);
  m_ui->assetTree->resizeColumnToContents(AssetTreeModel::NameColumn);
  for (const std::string& warning : asset->warnings)
    log(tr("warning: %1: %2").arg(path, QString::fromStdString(warning)));
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
  if (m_progress)
    m_progress->reset();
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
  QString html = tr("<h2>%1</h2><p>%2 · %3 cm per file unit (%4)</p>")
                     .arg(QFileInfo(QString::fromStdString(asset.sourcePath)).fileName().toHtmlEscaped(),
                          QString::fromStdString(asset.format).toHtmlEscaped())
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
  m_ui->summaryLabel->setText(html);
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
  QSettings settings;
  settings.setValue("mainWindow/geometry", saveGeometry());
  settings.setValue("mainWindow/state", saveState());
  cancelImport();
  QMainWindow::closeEvent(event);
}

} // namespace mlod
