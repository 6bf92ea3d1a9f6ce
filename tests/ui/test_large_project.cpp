// Qt Test: the studio opening large projects (issue 29: a project listing one asset 20,000
// times did not open in a minute). The work is checked by what it does, never by a clock:
// identical asset files import once and are shared, and every asset gets its row.
// Asset paths that climb out of the project's folder are refused, naming the path.

#include "editor/document/document.h"
#include "editor/main_window.h"
#include "editor/models/asset_tree.h"

#include <QFile>
#include <QMessageBox>
#include <QSignalSpy>
#include <QTemporaryDir>
#include <QTest>

using mlod::MainWindow;

class TestLargeProject : public QObject {
  Q_OBJECT

private:
  // A version 3 project at `path` listing `assets` (JSON objects, comma-separated).
  static bool writeProject(const QString& path, const QString& assets) {
    QFile file(path);
    if (!file.open(QIODevice::WriteOnly | QIODevice::Truncate))
      return false;
    return file.write(QString(R"({"format":"motionlod-project","version":3,"alpha":5,"mode":"greedy",)"
                       R"("lods":{"projection":{"vertical_fov_degrees":60,"viewport_height_pixels":1080},)"
                       R"("bounding_radius_cm":0,"levels":[{"name":"LOD0","threshold":0,"mesh_ratio":1,)"
                       R"("switch_distance_cm":0,"pixel_error":0,"screen_size_pixels":0,"motion_error_cm":0,)"
                       R"("mesh_error_cm":0,"triangles":0,"active_joints":0}]},"assets":[%1]})")
                   .arg(assets)
                          .toUtf8()) > 0;
  }

private slots:
  void initTestCase() { QCoreApplication::setOrganizationName("MotionLODTest"); }

  // Guards the open of a project naming one file thousands of times, under four spellings
  // (plain, "./", "sub/..", a symlink) and at two units: two imports (one per unit), every
  // asset sharing its import, one row per asset.
  void identicalAssetsImportOnce() {
    QTemporaryDir dir;
    QVERIFY(QFile::copy(MLOD_SAMPLE, dir.filePath("sample.bvh")));
    QVERIFY(QFile::link(dir.filePath("sample.bvh"), dir.filePath("link.bvh")));
    const int copies = 4000;
    const QStringList spellings{"sample.bvh", "./sample.bvh", "sub/../sample.bvh", "link.bvh"};
    QStringList assets;
    for (int i = 0; i < copies; ++i)
      assets << QString(R"({"path":"%1","joints":{}})").arg(spellings[i % spellings.size()]);
    const int inCm = 3; // the same file at another unit is another import
    for (int i = 0; i < inCm; ++i)
      assets << R"({"path":"sample.bvh","unit_scale":100,"joints":{}})";
    const QString path = dir.filePath("large.mlod");
    QVERIFY(writeProject(path, assets.join(',')));

    MainWindow window;
    QSignalSpy opened(window.document(), &mlod::Document::projectOpened);
    QVERIFY(window.openProject(path));
    QVERIFY(opened.wait(120000));
    QCOMPARE(opened.first().at(0).toBool(), true);

    const mlod::Document* document = window.document();
    QCOMPARE(document->assetCount(), copies + inCm);
    QCOMPARE(document->importCount(), 2);
    for (int i = 0; i < copies; ++i)
      QVERIFY(document->asset(i) && document->asset(i) == document->asset(0));
    for (int i = copies; i < copies + inCm; ++i)
      QVERIFY(document->asset(i) && document->asset(i) == document->asset(copies));
    QCOMPARE(document->asset(copies)->unitScale, 100.0);
    QVERIFY(document->asset(0)->unitScale != 100.0);
    QCOMPARE(window.assetModel()->rowCount(), copies + inCm);
    QCOMPARE(window.assetModel()->assetCount(), copies + inCm);
    QVERIFY(!window.assetModel()->isMissing(copies + inCm - 1));
    // the rows below an asset are made when it is expanded, not for every asset on open
    mlod::AssetTreeModel* model = window.assetModel();
    const QModelIndex first = model->index(0, 0);
    QVERIFY(model->hasChildren(first));
    QCOMPARE(model->QStandardItemModel::rowCount(first), 0);
    QVERIFY(model->canFetchMore(first));
    model->fetchMore(first);
    QCOMPARE(model->rowCount(first), 3); // skeleton, clips, meshes
    QCOMPARE(model->index(0, mlod::AssetTreeModel::DetailColumn, first).data().toString(), QString("38 joints"));
    QCOMPARE(model->QStandardItemModel::rowCount(model->index(1, 0)), 0);
  }

  // Guards issue 29's `../../../../../../etc/passwd`: a relative asset path leaving the
  // project's folder is refused (a hidden window never asks), the error names the path, and
  // nothing is opened.
  void assetOutsideTheFolderIsRefused() {
    QTemporaryDir dir;
    const QString climbing = "../../../../../../etc/passwd";
    const QString path = dir.filePath("climb.mlod");
    QVERIFY(writeProject(path, QString(R"({"path":"%1","joints":{}})").arg(climbing)));
    MainWindow window;
    QVERIFY(!window.openProject(path));
    QCOMPARE(window.document()->assetCount(), 0);
    QCOMPARE(window.document()->importCount(), 0);
    auto* box = window.findChild<QMessageBox*>("errorBox");
    QVERIFY(box);
    QVERIFY2(box->informativeText().contains(climbing), qPrintable(box->informativeText()));
  }
};

QTEST_MAIN(TestLargeProject)
#include "test_large_project.moc"
