// Qt Test driving the studio's main window: import (off the UI thread, through the
// sandboxed importer), errors, cancel, shortcuts and a rendered window.

#include "editor/document/document.h"
#include "editor/import_job.h"
#include "editor/main_window.h"
#include "editor/models/asset_tree.h"
#include "editor/studio/window_fit.h"
#include "editor/views/help_browser.h"
#include "editor/views/job_progress.h"
#include "test_files.h"
#include "event_conditions.h"

#include <QAction>
#include <QDockWidget>
#include <QImage>
#include <QMainWindow>
#include <QMessageBox>
#include <QScreen>
#include <QSignalSpy>
#include <QStatusBar>
#include <QTemporaryDir>
#include <QTest>
#include <QTextBrowser>
#include <QTextDocument>
#include <QTreeView>

#include <unistd.h>

using mlod::AssetTreeModel;
using mlod::MainWindow;
using mlod::test::ShowCounter;
using mlod::test::timersOfAtMostHaveFired;

class TestMainWindow : public QObject {
  Q_OBJECT

private:
  // Imports and waits for importFinished; returns its arguments.
  static QList<QVariant> importAndWait(MainWindow& window, const QString& path) {
    QSignalSpy spy(&window, &MainWindow::importFinished);
    window.importFile(path);
    if (!spy.wait(60000) || spy.isEmpty())
      return {};
    return spy.takeFirst();
  }

private slots:
  void initTestCase() { QCoreApplication::setOrganizationName("MotionLODTest"); }

  // The bundled sample imports; its skeleton shows as a joint tree with the CMU names.
  void importShowsSkeletonClipsAndMeshes() {
    MainWindow window;
    window.show();
    QVERIFY(QTest::qWaitForWindowExposed(&window));
    const QList<QVariant> result = importAndWait(window, MLOD_SAMPLE);
    QVERIFY(!result.isEmpty());
    QCOMPARE(result[0].toBool(), true);
    AssetTreeModel* model = window.assetModel();
    QCOMPARE(model->assetCount(), 1);
    const QModelIndex asset = model->index(0, 0);
    QCOMPARE(model->data(asset).toString(), QString("cmu_01_01_excerpt.bvh"));
    const QModelIndex skeleton = model->index(0, 0, asset);
    QCOMPARE(model->data(skeleton).toString(), QString("Skeleton"));
    QCOMPARE(model->data(model->index(0, AssetTreeModel::DetailColumn, asset)).toString(), QString("38 joints"));
    const QModelIndex hips = model->index(0, 0, skeleton);
    QCOMPARE(model->data(hips).toString(), QString("Hips"));
    QCOMPARE(model->rowCount(hips), 3); // LHipJoint, RHipJoint, LowerBack
    const QModelIndex clips = model->index(1, 0, asset);
    QCOMPARE(model->data(model->index(0, AssetTreeModel::DetailColumn, clips)).toString(),
             QString("480 frames · 120 fps · 3.99 s"));
    QVERIFY(window.logText().contains("Imported cmu_01_01_excerpt.bvh: 38 joints, 1 clip, 0 meshes"));
    QVERIFY(window.statusBar()->currentMessage().contains("Imported"));
  }

  // A broken file: the log says why, a non-modal message box appears, the window lives on.
  void importFailureIsReported() {
    QTemporaryDir dir;
    const QString empty = dir.filePath("empty.bvh");
    QFile file(empty);
    QVERIFY(file.open(QIODevice::WriteOnly));
    file.close();
    MainWindow window;
    window.show();
    const QList<QVariant> result = importAndWait(window, empty);
    QVERIFY(!result.isEmpty());
    QCOMPARE(result[0].toBool(), false);
    QVERIFY(result[2].toString().contains("empty"));
    QVERIFY(window.logText().contains("error: " + empty + ": the file is empty"));
    auto* box = window.findChild<QMessageBox*>();
    QVERIFY(box);
    QVERIFY(box->isVisible());
    QCOMPARE(box->informativeText(), QString("the file is empty"));
    box->close();
    QCOMPARE(window.assetModel()->assetCount(), 0);
    // The window still imports afterwards.
    QCOMPARE(importAndWait(window, MLOD_SAMPLE).value(0).toBool(), true);
  }

  // Cancel stops a runaway import (a file that makes Assimp allocate without end): its
  // worker is running when Cancel comes, and is gone after it.
  void cancelStopsImport() {
    MainWindow window;
    window.show();
    mlod::IsolationLimits limits;
    limits.memoryBytes = 0; // without a limit this file keeps Assimp allocating for minutes
    window.importJob()->setLimits(limits);
    QSignalSpy spy(&window, &MainWindow::importFinished);
    window.importFile(QString(MLOD_ASSIMP_MODELS) + "/invalid/OutOfMemory.off");
    QVERIFY(window.isImporting());
    const pid_t worker = mlod::test::workerOf(::getpid(), 20.0);
    QVERIFY2(worker > 0, "no import worker started");
    QVERIFY2(spy.isEmpty(), qPrintable(spy.isEmpty() ? QString() : spy.first()[2].toString()));
    window.cancelImport();
    QVERIFY(spy.wait(20000));
    QCOMPARE(spy.first()[0].toBool(), false);
    QCOMPARE(spy.first()[2].toString(), QString("import cancelled"));
    QVERIFY(!window.isImporting());
    QTRY_VERIFY_WITH_TIMEOUT(!mlod::test::runs(worker), 10000);
  }

  // A second import while one runs is refused and logged, not queued silently: a third
  // import after the first ends is the next one to finish (a queued second would finish
  // before it, or have it refused).
  void secondImportWhileRunningIsRefused() {
    MainWindow window;
    QSignalSpy spy(&window, &MainWindow::importFinished);
    window.importFile(MLOD_SAMPLE);
    window.importFile(MLOD_SAMPLE);
    QVERIFY(window.logText().contains("already running"));
    QVERIFY(spy.wait(60000));
    QCOMPARE(spy.count(), 1);
    const QString third = QString(MLOD_ASSIMP_MODELS) + "/BVH/01_01.bvh";
    const QList<QVariant> result = importAndWait(window, third);
    QVERIFY(!result.isEmpty());
    QCOMPARE(result[1].toString(), third);
    QCOMPARE(result[0].toBool(), true);
    QCOMPARE(spy.count(), 2);
    QCOMPARE(window.logText().count("already running"), 1);
    QCOMPARE(window.assetModel()->assetCount(), 2);
  }

  // The import unit applies to the next import and is remembered (QSettings).
  void importUnitAppliesAndPersists() {
    {
      MainWindow window;
      auto* cmu = window.findChild<QAction*>("actionUnit_cmu");
      QVERIFY(cmu);
      cmu->trigger();
      QVERIFY(cmu->isChecked());
      QVERIFY(qAbs(window.importUnitScale() - 2.54 / 0.45) < 1e-9);
      QCOMPARE(importAndWait(window, MLOD_SAMPLE).value(0).toBool(), true);
      const mlod::Asset* asset = window.assetModel()->assetAt(0);
      QVERIFY(asset);
      QVERIFY(qAbs(asset->unitScale - 2.54 / 0.45) < 1e-9);
      // LeftUpLeg's offset is (1.36306, -1.79463, 0.83929) file units.
      const glm::vec3 offset = asset->skeleton.joints[std::size_t(asset->skeleton.find("LeftUpLeg"))].rest.translation;
      QVERIFY(qAbs(offset.x - 1.36306f * 2.54f / 0.45f) < 1e-3f);
    }
    MainWindow reopened;
    QVERIFY(qAbs(reopened.importUnitScale() - 2.54 / 0.45) < 1e-9);
    // The remembered unit is checked from the start (it was not: the menu was filled after
    // the saved unit was applied).
    QVERIFY(reopened.findChild<QAction*>("actionUnit_cmu")->isChecked());
    reopened.findChild<QAction*>("actionUnitFromFile")->trigger();
    QCOMPARE(reopened.importUnitScale(), 0.0);
    MainWindow fromFile;
    QVERIFY(fromFile.findChild<QAction*>("actionUnitFromFile")->isChecked());
    QVERIFY(!fromFile.findChild<QAction*>("actionUnit_cmu")->isChecked());
  }

  // Edit > Asset Unit lists the presets with the unit of the asset in view checked; another
  // preset imports the asset again at that unit (and the check follows).
  void assetUnitMenuChecksTheAssetsUnit() {
    MainWindow window;
    window.findChild<QAction*>("actionUnitFromFile")->trigger();
    QCOMPARE(importAndWait(window, MLOD_SAMPLE).value(0).toBool(), true);
    auto* cmu = window.findChild<QAction*>("actionAssetUnit_cmu");
    auto* metres = window.findChild<QAction*>("actionAssetUnit_m");
    QVERIFY(cmu && metres);
    QVERIFY(cmu->isChecked()); // the guessed unit
    QVERIFY(!metres->isChecked());
    QSignalSpy changed(window.document(), &mlod::Document::unitScaleChanged);
    metres->trigger();
    QVERIFY(changed.wait(60000));
    QCOMPARE(changed.first().at(0).toBool(), true);
    QCOMPARE(window.document()->asset(0)->unitScale, 100.0);
    QVERIFY(metres->isChecked());
    QVERIFY(!cmu->isChecked());
    QVERIFY(window.logText().contains("Edit: "));
  }

  // View > Reset Layout puts a floated, hidden dock back where a first run has it.
  void resetLayoutDocksEverything() {
    MainWindow window;
    window.show();
    QVERIFY(QTest::qWaitForWindowExposed(&window));
    auto* assets = window.findChild<QDockWidget*>("assetsDock");
    auto* levels = window.findChild<QDockWidget*>("levelsDock");
    QVERIFY(assets && levels);
    assets->setFloating(true);
    levels->hide();
    window.crowdDock()->setFloating(true);
    window.findChild<QAction*>("actionResetLayout")->trigger();
    QVERIFY(!assets->isFloating());
    QVERIFY(levels->isVisible());
    QVERIFY(!window.crowdDock()->isFloating());
    QCOMPARE(window.dockWidgetArea(assets), Qt::LeftDockWidgetArea);
    QCOMPARE(window.dockWidgetArea(window.crowdDock()), Qt::RightDockWidgetArea);
    QCOMPARE(window.centralWidget()->objectName(), QStringLiteral("viewportPanel"));
  }

  // Help > User Guide (F1) shows the guide with its pictures.
  void helpShowsTheUserGuide() {
    MainWindow window;
    auto* guide = window.findChild<QAction*>("actionUserGuide");
    QVERIFY(guide);
    QCOMPARE(guide->shortcut(), QKeySequence(QKeySequence::HelpContents));
    guide->trigger();
    auto* help = window.findChild<mlod::HelpBrowser*>("helpBrowser");
    QVERIFY(help);
    QVERIFY(help->isVisible());
    QVERIFY(help->browser()->toPlainText().contains("Motion LOD"));
    const QString text = help->browser()->toPlainText(); // the whole guide, to its last section
    QVERIFY2(text.contains("Troubleshooting") && text.contains("Importing, and units"),
             qPrintable(QString("%1 characters: %2").arg(text.size()).arg(text.left(300))));
    const QVariant picture =
        help->browser()->document()->resource(QTextDocument::ImageResource, QUrl("images/studio-overview.png"));
    QVERIFY(picture.isValid());
  }

  // A file that states no unit gets the preset that makes it a human height, and the
  // Assets dock says how tall it is and that the unit was guessed.
  void guessedUnitIsShown() {
    MainWindow window;
    window.findChild<QAction*>("actionUnitFromFile")->trigger();
    QCOMPARE(importAndWait(window, MLOD_SAMPLE).value(0).toBool(), true);
    const mlod::Asset* asset = window.assetModel()->assetAt(0);
    QVERIFY(asset);
    QCOMPARE(QString::fromStdString(asset->unitSource), QString("guessed"));
    QVERIFY(qAbs(asset->unitScale - 2.54 / 0.45) < 1e-9); // a CMU skeleton
    const QString detail = window.assetModel()->index(0, AssetTreeModel::DetailColumn).data().toString();
    QVERIFY2(detail.contains(" m tall") && detail.contains("(guessed)"), qPrintable(detail));
    QVERIFY(window.logText().contains("states no unit: guessed 5.6444 cm per file unit"));
  }

  // Progress dialogs show only while work runs: after an import and its clustering they are
  // hidden, and stay hidden (QProgressDialog's own timer used to show them afterwards).
  void progressDialogsHideWhenTheJobEnds() {
    MainWindow window;
    window.show();
    QVERIFY(QTest::qWaitForWindowExposed(&window));
    QSignalSpy analysed(window.document(), &mlod::Document::analysisFinished);
    QCOMPARE(importAndWait(window, MLOD_SAMPLE).value(0).toBool(), true);
    QVERIFY(analysed.wait(60000));
    QVERIFY(window.importProgress() && window.analysisProgress() && window.levelsProgress());
    const ShowCounter importShows(window.importProgress());
    const ShowCounter analysisShows(window.analysisProgress());
    const ShowCounter levelsShows(window.levelsProgress());
    QVERIFY(timersOfAtMostHaveFired(mlod::JobProgress::kShowDelayMs)); // past every show timer
    QVERIFY(!window.importProgress()->isVisible());
    QVERIFY(!window.analysisProgress()->isVisible());
    QVERIFY(!window.levelsProgress()->isVisible());
    QCOMPARE(importShows.count() + analysisShows.count() + levelsShows.count(), 0);
  }

  // The dialog itself: shown once a job has run kShowDelayMs, hidden when it ends; a job
  // shorter than that never shows it, not even for a moment (counted by Show events).
  void jobProgressShowsOnlyForLongWork() {
    QWidget parent;
    parent.show();
    mlod::JobProgress progress("Work", "Cancel", &parent);
    const ShowCounter shows(&progress);
    // a short job: one pass of the event loop between its start and its end
    progress.begin("short", 10);
    QCoreApplication::processEvents();
    progress.finish();
    QVERIFY(timersOfAtMostHaveFired(mlod::JobProgress::kShowDelayMs));
    QCOMPARE(shows.count(), 0);
    QVERIFY(!progress.isVisible());
    progress.begin("long", 10);
    QTRY_VERIFY_WITH_TIMEOUT(progress.isVisible(), 5000);
    QCOMPARE(shows.count(), 1);
    progress.step(5, 10);
    QCOMPARE(progress.value(), 5);
    progress.finish();
    QVERIFY(!progress.isVisible());
    QVERIFY(timersOfAtMostHaveFired(mlod::JobProgress::kShowDelayMs));
    QVERIFY(!progress.isVisible());
    QCOMPARE(shows.count(), 1);
  }

  // A project whose "current" fields are all out of range (hand-edited, or from a damaged
  // file) opens without a crash at the nearest valid view (it crashed in
  // JointTreeModel::data and MainWindow::refreshStatus).
  void projectWithEveryCurrentFieldOutOfRangeOpens() {
    QTemporaryDir dir;
    for (const QString& current :
         {QString(R"({"asset":2147483647,"clip":2147483648,"level":2147483648,"joint":"nope"})"),
          QString(R"({"asset":-7,"clip":-1,"level":-1,"joint":""})"),
          QString(R"({"asset":0,"clip":99,"level":99,"joint":"Hips"})")}) {
      const QString path = dir.filePath("out_of_range.mlod");
      QFile file(path);
      QVERIFY(file.open(QIODevice::WriteOnly | QIODevice::Truncate));
      file.write(QString(R"({"format":"motionlod-project","version":1,"alpha":5,"mode":"greedy",)"
                         R"("levels":[{"threshold":5},{"threshold":50}],)"
                         R"("assets":[{"path":"%1","unit_scale":5.644444444,"joints":{}}],"current":%2})")
                     .arg(QString(MLOD_SAMPLE), current)
                     .toUtf8());
      file.close();
      MainWindow window;
      window.show();
      QSignalSpy opened(window.document(), &mlod::Document::projectOpened);
      QVERIFY2(window.openProject(path), qPrintable(current));
      QVERIFY(opened.wait(60000));
      const mlod::Document* document = window.document();
      QTRY_VERIFY_WITH_TIMEOUT(!document->isLoading() && !document->isAnalysing(), 60000); // the views refresh
      QVERIFY(document->currentLevel() >= 0 && document->currentLevel() < document->levelCount());
      QVERIFY(document->currentAsset() >= -1 && document->currentAsset() < document->assetCount());
      QVERIFY(!window.statusText().isEmpty());
      window.grab(); // paints every view
    }
  }

  // The common actions have their standard shortcuts and tooltips.
  void actionsHaveShortcuts() {
    MainWindow window;
    auto* open = window.findChild<QAction*>("actionOpen");
    auto* quit = window.findChild<QAction*>("actionQuit");
    QVERIFY(open && quit);
    QCOMPARE(open->shortcut(), QKeySequence(QKeySequence::Open));
    QCOMPARE(quit->shortcut(), QKeySequence("Ctrl+Q"));
    QVERIFY(!open->toolTip().isEmpty());
  }

  // The first window fits the screen, its frame included (issue 26, item 7: 1600 x 1000 plus
  // a title bar on a 1600 x 1000 screen hid the status bar). The rule on the issue's screen
  // and a larger one, then the studio's window shown by it on this screen.
  void firstWindowFitsTheScreen() {
    const QMargins titleBar(1, 30, 1, 1);
    const QRect small = mlod::firstWindowGeometry({1600, 1000}, QRect(0, 0, 1600, 1000), titleBar);
    QCOMPARE(small, QRect(1, 30, 1598, 969));
    QVERIFY(QRect(0, 0, 1600, 1000).contains(small.marginsAdded(titleBar)));
    const QRect large = mlod::firstWindowGeometry({1600, 1000}, QRect(0, 24, 2560, 1416), titleBar);
    QCOMPARE(large.size(), QSize(1600, 1000)); // room enough: the size it is designed for, centred
    QCOMPARE(large.left() - titleBar.left() - 0, (2560 - 1602) / 2);
    QCOMPARE(large.top() - titleBar.top() - 24, (1416 - 1031) / 2);
    QVERIFY(QRect(0, 24, 2560, 1416).contains(large.marginsAdded(titleBar)));

    // A main window with a status bar shown by it on this screen (offscreen: 800 x 800, so
    // 1600 x 1000 must shrink): its frame inside the available area, the status bar on screen.
    // The studio's own window too, where the screen is at least its minimum size.
    QMainWindow plain;
    plain.statusBar()->showMessage("Ready");
    MainWindow studio;
    for (QMainWindow* window : {&plain, static_cast<QMainWindow*>(&studio)}) {
      const QRect available = window->screen()->availableGeometry();
      const QSize least = window->minimumSizeHint().expandedTo(window->minimumSize());
      if (least.width() > available.width() || least.height() > available.height()) {
        qInfo("the studio's window needs at least %d x %d, the screen has %d x %d: not shown", least.width(),
              least.height(), available.width(), available.height());
        continue;
      }
      mlod::showFitted(window, {1600, 1000});
      QVERIFY(QTest::qWaitForWindowExposed(window));
      const QRect frame = window->frameGeometry();
      QTRY_VERIFY2(available.contains(window->frameGeometry()),
                   qPrintable(QString("frame %1,%2 %3 x %4 on %5,%6 %7 x %8")
                                  .arg(frame.x())
                                  .arg(frame.y())
                                  .arg(frame.width())
                                  .arg(frame.height())
                                  .arg(available.x())
                                  .arg(available.y())
                                  .arg(available.width())
                                  .arg(available.height())));
      // shrunk by a frame at most, not more
      QVERIFY(window->width() >= std::min(1600, available.width()) - 64);
      QVERIFY(window->height() >= std::min(1000, available.height()) - 64);
      QVERIFY(window->statusBar()->isVisible());
      QVERIFY(available.contains(window->statusBar()->mapToGlobal(window->statusBar()->rect().bottomRight())));
    }
  }

  // The window renders: the grabbed image is not blank after an import.
  void windowRendersSomething() {
    MainWindow window;
    window.resize(1000, 700);
    window.show();
    QVERIFY(QTest::qWaitForWindowExposed(&window));
    QCOMPARE(importAndWait(window, MLOD_SAMPLE).value(0).toBool(), true);
    const QImage image = window.grab().toImage();
    QVERIFY(!image.isNull());
    QSet<QRgb> colours;
    for (int y = 0; y < image.height(); y += 7)
      for (int x = 0; x < image.width(); x += 7)
        colours.insert(image.pixel(x, y));
    QVERIFY2(colours.size() > 5, "the window image is blank");
  }
};

QTEST_MAIN(TestMainWindow)
#include "test_main_window.moc"
