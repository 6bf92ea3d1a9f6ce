// Qt Test driving File > Export… (the Export dialog): the sample exported with the bundle
// plugin (plugin combo, options built from the plugin's options with their help as
// tooltips, levels ticked, output path), the file read back by the runtime; cancel leaves
// nothing; a missing output path or an unwritable folder is said in the dialog; the
// main window's File > Export… action (Ctrl+E) opens it.

#include "editor/document/document.h"
#include "editor/document/edits.h"
#include "editor/main_window.h"
#include "editor/viewport/crowd_panel.h"
#include "editor/viewport/level_meshes.h"
#include "editor/viewport/playback.h"
#include "editor/views/export_dialog.h"
#include "io/importer.h"
#include "runtime/bundle.h"
#include "sdk/plugin_host.h"

#include "event_conditions.h"

#include <QAction>
#include <QCheckBox>
#include <QComboBox>
#include <QDir>
#include <QFileInfo>
#include <QLabel>
#include <QLineEdit>
#include <QListWidget>
#include <QProgressDialog>
#include <QScopeGuard>
#include <QPushButton>
#include <QSignalSpy>
#include <QTemporaryDir>
#include <QSpinBox>
#include <QSettings>
#include <QTest>

#include <atomic>
#include <chrono>
#include <memory>
#include <thread>

using namespace mlod;

class TestExportDialog : public QObject {
  Q_OBJECT

private:
  PluginHost m_host;

  // A document holding the bundled sample at the CMU unit.
  static std::unique_ptr<Document> sampleDocument() {
    auto document = std::make_unique<Document>();
    ImportOptions options;
    options.unitScale = 2.54 / 0.45;
    Result<Asset> asset = importAsset(MLOD_SAMPLE, options);
    if (!asset)
      return nullptr;
    edit::addAsset(*document, std::make_shared<const Asset>(std::move(asset).value()), MLOD_SAMPLE, options.unitScale);
    document->setCurrentAsset(0);
    return document;
  }

  static void chooseBundle(ExportDialog& dialog) {
    const int index = dialog.pluginCombo()->findData("bundle");
    QVERIFY(index >= 0);
    dialog.pluginCombo()->setCurrentIndex(index);
  }

  static QStringList filesIn(const QString& dir) {
    return QDir(dir).entryList(QDir::Files | QDir::Hidden | QDir::NoDotAndDotDot);
  }

private slots:
  void initTestCase() {
    QCoreApplication::setOrganizationName("MotionLODTest");
    m_host.load({MLOD_PLUGIN_DIR});
    QVERIFY(m_host.exporter("bundle"));
  }

  void exportsTheSampleWithTheBundlePlugin() {
    std::unique_ptr<Document> document = sampleDocument();
    QVERIFY(document);
    ExportDialog dialog(document.get(), &m_host);
    dialog.show();
    QVERIFY(QTest::qWaitForWindowExposed(&dialog));
    QCOMPARE(dialog.exportedAsset(), 0);
    chooseBundle(dialog);
    // the form is the plugin's options as data, with their help as tooltips
    auto* manifest = qobject_cast<QCheckBox*>(dialog.optionWidget("manifest"));
    QVERIFY(manifest);
    QVERIFY(manifest->isChecked());
    QVERIFY(manifest->toolTip().contains("manifest") || manifest->toolTip().contains(".json"));
    QVERIFY(dialog.optionWidget("meshes"));
    QVERIFY(dialog.outputEdit()->text().endsWith(".mlodb"));
    // the project's levels (a new project: the original and four thresholds), all ticked; untick level 1
    QCOMPARE(dialog.levelsList()->count(), document->levelCount());
    dialog.levelsList()->item(1)->setCheckState(Qt::Unchecked);

    QTemporaryDir dir;
    const QString path = dir.filePath("sample.mlodb");
    dialog.outputEdit()->setText(path);
    QSignalSpy finished(&dialog, &ExportDialog::exportFinished);
    const QString shots = qEnvironmentVariable("MLOD_SCREENSHOT_DIR"); // for people: what the dialog looks like
    if (!shots.isEmpty())
      QVERIFY(dialog.grab().save(QDir(shots).filePath("export_dialog.png")));
    QTest::mouseClick(dialog.findChild<QPushButton*>("exportButton"), Qt::LeftButton);
    QVERIFY(dialog.isRunning());
    QVERIFY(finished.wait(60000));
    QCOMPARE(finished.first().at(0).toBool(), true);
    QVERIFY(!dialog.isRunning());
    QVERIFY(dialog.resultLabel()->text().contains(QDir(dir.path()).absolutePath()));
    QCOMPARE(filesIn(dir.path()), QStringList({"sample.mlodb", "sample.mlodb.json"}));
    if (!shots.isEmpty()) {
      // let the layout take the result's lines
      QVERIFY(mlod::test::settles([&] { return QList<QSize>{dialog.size(), dialog.resultLabel()->size()}; }));
      QVERIFY(dialog.grab().save(QDir(shots).filePath("export_dialog_done.png")));
    }

    std::string error;
    std::optional<Bundle> bundle = readBundleFile(path.toStdString(), &error);
    QVERIFY2(bundle, error.c_str());
    QCOMPARE(int(bundle->levels.size()), document->levelCount() - 1);
    QCOMPARE(bundle->levels[0].index, 0);
    QCOMPARE(bundle->levels[1].index, 2);
    QCOMPARE(bundle->name, std::string("cmu_01_01_excerpt"));
    for (const BundleLevel& level : bundle->levels)
      QVERIFY(buildBundleLevel(level, &error));
  }

  // While an export runs the views' own background builds wait (Document::isWaitedJobRunning()):
  // the viewport's level mesh asked for meanwhile starts when the export ends, and one that
  // was being built (the viewport's, the Crowd's levels) is cancelled and built again then. Issue 26: the studio's export right
  // after opening a project shared two cores with the viewport's level mesh and the crowd's
  // levels and took 6.2 s where `motionlod export` took 4.6 s.
  void backgroundBuildsWaitForTheExport() {
    std::unique_ptr<Document> document = sampleDocument();
    QVERIFY(document);
    QVERIFY(document->levelCount() > 2);
    LevelMeshes meshes(document.get());
    QSignalSpy ready(&meshes, &LevelMeshes::ready);
    QVERIFY(!meshes.request(0, 2)); // being built when the export starts
    QVERIFY(meshes.isBuilding());
    Playback playback;
    CrowdPanel crowd(document.get(), &playback);
    QSignalSpy crowdReady(&crowd, &CrowdPanel::levelsReady);
    crowd.show(); // builds its levels once shown
    QTRY_VERIFY(crowd.isBuilding());
    ExportDialog dialog(document.get(), &m_host);
    dialog.show();
    chooseBundle(dialog);
    QTemporaryDir dir;
    dialog.outputEdit()->setText(dir.filePath("waited.mlodb"));
    std::atomic<bool> release{false}; // the export runs until the test has looked
    const auto releaseOnReturn = qScopeGuard([&release] { release.store(true); });
    dialog.setWorkerHook([&release](const std::atomic<bool>&) {
      for (int i = 0; i < 30000 && !release.load(); ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    });
    QSignalSpy exporting(document.get(), &Document::waitedJobChanged);
    QSignalSpy finished(&dialog, &ExportDialog::exportFinished);
    dialog.startExport();
    QVERIFY(dialog.isRunning());
    QVERIFY(document->isWaitedJobRunning());
    QCOMPARE(exporting.count(), 1);
    QTRY_VERIFY(!meshes.isBuilding()); // a build under way was cancelled
    QTRY_VERIFY(!crowd.isBuilding());  // the crowd's too
    QVERIFY(!meshes.request(0, 1));    // asked for during the export: waits
    QVERIFY(!meshes.isBuilding());
    crowd.requestLevels(); // the same
    QTRY_VERIFY(!crowd.isBuilding());
    // (the sample's builds are quick: one that had ended when the export started may still
    // say so once the events already posted are delivered; nothing asked for during it does)
    const auto settle = [] {
      QCoreApplication::sendPostedEvents();
      QCoreApplication::processEvents();
    };
    settle();
    const int buildsBefore = meshes.builds();
    const int readyBefore = int(ready.count()), crowdReadyBefore = int(crowdReady.count());
    for (const QList<QVariant>& signal : ready)
      QCOMPARE(signal.at(1).toInt(), 2);
    settle();
    QVERIFY(!meshes.isBuilding() && !crowd.isBuilding());
    QCOMPARE(int(ready.count()), readyBefore);
    QCOMPARE(int(crowdReady.count()), crowdReadyBefore);
    release.store(true);
    QVERIFY(finished.wait(60000));
    QVERIFY(finished.first().at(0).toBool());
    QVERIFY(!document->isWaitedJobRunning());
    QCOMPARE(exporting.count(), 2);
    QVERIFY(meshes.isBuilding()); // the latest request, at once
    QTRY_COMPARE_WITH_TIMEOUT(int(ready.count()), readyBefore + 1, 60000);
    QCOMPARE(ready.last().at(1).toInt(), 1);
    QCOMPARE(meshes.builds(), buildsBefore + 1); // a cancelled build does not count
    QTRY_COMPARE_WITH_TIMEOUT(int(crowdReady.count()), crowdReadyBefore + 1, 60000); // built after the export
    QVERIFY2(crowdReady.last().at(0).toBool(), qPrintable(crowdReady.last().at(1).toString()));
  }

  void cancelLeavesNothing() {
    std::unique_ptr<Document> document = sampleDocument();
    QVERIFY(document);
    ExportDialog dialog(document.get(), &m_host);
    dialog.show();
    chooseBundle(dialog);
    QTemporaryDir dir;
    dialog.outputEdit()->setText(dir.filePath("cancelled.mlodb"));
    // the worker waits until the user has pressed Cancel, so the test does not race it
    dialog.setWorkerHook([](const std::atomic<bool>& cancel) {
      for (int i = 0; i < 5000 && !cancel.load(); ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    });
    QSignalSpy finished(&dialog, &ExportDialog::exportFinished);
    dialog.startExport();
    QProgressDialog* progress = dialog.progressDialog();
    QVERIFY(progress);
    QTRY_VERIFY(progress->isVisible());
    QPushButton* cancel = progress->findChild<QPushButton*>();
    QVERIFY(cancel);
    QCOMPARE(cancel->text(), QString("Cancel"));
    cancel->click(); // as Space on the focused button does: no race with the window's layout under load
    QVERIFY(finished.wait(60000));
    QCOMPARE(finished.first().at(0).toBool(), false);
    QVERIFY(finished.first().at(1).toString().startsWith("cancelled"));
    QVERIFY(dialog.resultLabel()->text().contains("Nothing was written"));
    QVERIFY(filesIn(dir.path()).isEmpty());
  }

  void badOutputIsSaidInTheDialog() {
    std::unique_ptr<Document> document = sampleDocument();
    QVERIFY(document);
    ExportDialog dialog(document.get(), &m_host);
    chooseBundle(dialog);
    dialog.outputEdit()->clear();
    dialog.startExport();
    QVERIFY(!dialog.isRunning());
    QVERIFY(dialog.resultLabel()->text().contains("Choose the output file"));

    QTemporaryDir dir;
    dialog.outputEdit()->setText(dir.filePath("no/such/folder/x.mlodb"));
    QSignalSpy finished(&dialog, &ExportDialog::exportFinished);
    dialog.startExport();
    QVERIFY(finished.wait(60000));
    QCOMPARE(finished.first().at(0).toBool(), false);
    QVERIFY(dialog.resultLabel()->text().contains("Nothing was written"));
    QVERIFY(dialog.resultLabel()->text().contains("cannot write"));
    QVERIFY(filesIn(dir.path()).isEmpty());

    for (int i = 0; i < dialog.levelsList()->count(); ++i)
      dialog.levelsList()->item(i)->setCheckState(Qt::Unchecked);
    dialog.startExport();
    QVERIFY(dialog.resultLabel()->text().contains("Tick at least one level"));
  }

  // What the format cannot hold is refused before the build, as the CLI refuses it
  // (Exporter::planProblem()): a mesh without a skeleton to the bundle plugin. The studio's
  // export used to start building and fail only in the plugin.
  void whatTheFormatCannotHoldIsRefusedAtOnce() {
    auto document = std::make_unique<Document>();
    const QString mesh = QStringLiteral(MLOD_ASSIMP_MODELS "/OBJ/spider.obj");
    Result<Asset> asset = importAsset(mesh.toStdString(), {});
    QVERIFY2(asset, asset ? "" : asset.message().c_str());
    QVERIFY(asset->skeleton.empty());
    edit::addAsset(*document, std::make_shared<const Asset>(std::move(asset).value()), mesh, 1.0);
    document->setCurrentAsset(0);
    ExportDialog dialog(document.get(), &m_host);
    chooseBundle(dialog);
    QTemporaryDir dir;
    dialog.outputEdit()->setText(dir.filePath("spider.mlodb"));
    QSignalSpy finished(&dialog, &ExportDialog::exportFinished);
    dialog.startExport();
    QVERIFY(!dialog.isRunning()); // refused before any worker started
    QVERIFY(dialog.resultLabel()->text().contains("Nothing was written"));
    QVERIFY2(dialog.resultLabel()->text().contains("has no skeleton"), qPrintable(dialog.resultLabel()->text()));
    QVERIFY(filesIn(dir.path()).isEmpty());
  }

  // The output's suffix must be the plugin's: another format's is refused (nothing written),
  // none gets the plugin's; a new plugin or option clears the last result.
  void suffixMustMatchThePlugin() {
    std::unique_ptr<Document> document = sampleDocument();
    QVERIFY(document);
    ExportDialog dialog(document.get(), &m_host);
    chooseBundle(dialog);
    QTemporaryDir dir;
    dialog.outputEdit()->setText(dir.filePath("character.glb"));
    dialog.startExport();
    QVERIFY(!dialog.isRunning());
    QVERIFY2(dialog.resultLabel()->text().contains("ends in .glb"), qPrintable(dialog.resultLabel()->text()));
    QVERIFY(filesIn(dir.path()).isEmpty());
    // An option changed: the message about the last try goes.
    for (QWidget* editor : dialog.findChildren<QWidget*>()) {
      if (!editor->objectName().startsWith("option_"))
        continue;
      if (auto* box = qobject_cast<QCheckBox*>(editor))
        box->toggle();
      else if (auto* spin = qobject_cast<QSpinBox*>(editor))
        spin->setValue(spin->value() == spin->minimum() ? spin->value() + 1 : spin->minimum());
      else if (auto* combo = qobject_cast<QComboBox*>(editor))
        combo->setCurrentIndex((combo->currentIndex() + 1) % combo->count());
      else
        continue;
      QVERIFY2(dialog.resultLabel()->text().isEmpty(), qPrintable(editor->objectName()));
      break;
    }
    if (dialog.pluginCombo()->count() > 1) { // another plugin: the same
      dialog.startExport();
      QVERIFY(!dialog.resultLabel()->text().isEmpty());
      dialog.pluginCombo()->setCurrentIndex((dialog.pluginCombo()->currentIndex() + 1) % dialog.pluginCombo()->count());
      QVERIFY(dialog.resultLabel()->text().isEmpty());
      chooseBundle(dialog);
    }
    // No suffix: the plugin's is added and the export runs.
    dialog.outputEdit()->setText(dir.filePath("character"));
    QSignalSpy finished(&dialog, &ExportDialog::exportFinished);
    dialog.startExport();
    QVERIFY(finished.wait(60000));
    QCOMPARE(finished.first().at(0).toBool(), true);
    QCOMPARE(dialog.outputEdit()->text(), dir.filePath("character.mlodb"));
    QVERIFY(QFileInfo::exists(dir.filePath("character.mlodb")));
  }

  // The default output folder is one the user can write to, never a read-only source folder.
  void defaultFolderIsWritable() {
    QTemporaryDir dir;
    // A folder nobody can write to, root included (a chmod'ed folder is writable to root,
    // as the tests run in CI): procfs's /proc/sys takes no new file.
    const QString readOnly = "/proc/sys";
    QVERIFY(QFileInfo(readOnly).isDir());
    QFile probe(readOnly + "/mlod-probe");
    QVERIFY2(!probe.open(QIODevice::WriteOnly), "/proc/sys took a file: the premise of this test is gone");
    QCOMPARE(firstWritableFolder({readOnly, dir.path()}), QFileInfo(dir.path()).absoluteFilePath());
    QCOMPARE(firstWritableFolder({QString(), dir.filePath("missing"), dir.path()}),
             QFileInfo(dir.path()).absoluteFilePath());
    QSettings().remove("export/lastDir");
    std::unique_ptr<Document> document = sampleDocument();
    QVERIFY(document);
    ExportDialog dialog(document.get(), &m_host);
    const QFileInfo folder(QFileInfo(dialog.outputEdit()->text()).absolutePath());
    QVERIFY2(folder.isDir() && folder.isWritable(), qPrintable(folder.absoluteFilePath()));
  }

  // File > Export… is there with Ctrl+E and opens the dialog.
  void mainWindowActionOpensTheDialog() {
    MainWindow window;
    auto* action = window.findChild<QAction*>("actionExport");
    QVERIFY(action);
    QCOMPARE(action->shortcut(), QKeySequence("Ctrl+E"));
    QVERIFY(!action->toolTip().isEmpty());
    action->trigger();
    auto* dialog = window.findChild<ExportDialog*>("exportDialog");
    QVERIFY(dialog);
    QVERIFY(dialog->isVisible());
    QCOMPARE(dialog->exportedAsset(), -1); // nothing imported: said, and Export disabled
    QVERIFY(!dialog->findChild<QPushButton*>("exportButton")->isEnabled());
    dialog->close();
  }
};

QTEST_MAIN(TestExportDialog)
#include "test_export_dialog.moc"
