// Qt Test driving the editor as a technical artist does: select joints, edit thresholds
// through the delegate, undo, lock, levels, projects (save, reopen, refuse, recover,
// relink), cancel, the Table 1 view against `motionlod simplify`, layout restore.
// Every figure compared is the document's own (no timed assertions).

#include "core/mapping/motion_mapping.h"
#include "core/project.h"
#include "core/project_package.h"
#include "editor/charts/statistics_view.h"
#include "editor/document/autosave.h"
#include "editor/document/document.h"
#include "editor/document/edits.h"
#include "editor/document/level_generator.h"
#include "editor/main_window.h"
#include "editor/models/asset_tree.h"
#include "editor/models/joint_tree_model.h"
#include "editor/models/levels_model.h"
#include "editor/models/mapping_model.h"
#include "editor/viewport/viewport_panel.h"
#include "editor/views/budget_dialog.h"
#include "editor/views/clustering_table_view.h"
#include "editor/views/export_dialog.h"
#include "editor/views/mapping_dialog.h"
#include "editor/views/trajectory_view.h"
#include "event_conditions.h"
#include "sdk/plugin_host.h"

#include <QAbstractButton>
#include <QChart>
#include <QCheckBox>
#include <QComboBox>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QFile>
#include <QFont>
#include <QGraphicsTextItem>
#include <QGraphicsView>
#include <QHeaderView>
#include <QInputDialog>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QLabel>
#include <QLineEdit>
#include <QLineSeries>
#include <QListWidget>
#include <QMessageBox>
#include <QProcess>
#include <QProgressDialog>
#include <QPushButton>
#include <QSettings>
#include <QSignalSpy>
#include <QSpinBox>
#include <QStatusBar>
#include <QStyle>
#include <QTabWidget>
#include <QTableView>
#include <QTableWidget>
#include <QTemporaryDir>
#include <QTest>
#include <QTimer>
#include <QToolButton>
#include <QTreeView>
#include <QUndoStack>
#include <QWheelEvent>
#include <memory>

using namespace mlod;

namespace {

// The figures a technical artist reads, per level: Table 1 and per joint.
struct Figures {
  std::vector<double> values;
  bool operator==(const Figures&) const = default;
};

Figures figuresOf(const Document& document) {
  Figures out;
  const auto analysis = document.analysis();
  if (!analysis)
    return out;
  for (const JpcLevelResult& level : analysis->levels) {
    out.values.insert(out.values.end(), {level.threshold, level.simplifiedPercent, double(level.clusterCount),
                                         level.maxError, level.maxJointPositionErrorCm, level.meanJointPositionErrorCm});
    for (const JointMetrics& joint : level.joints)
      out.values.insert(out.values.end(), {joint.threshold, double(joint.clusters), joint.simplifiedPercent, joint.maxError,
                                           double(joint.locked)});
  }
  return out;
}

QString tableText(const StatisticsView* view) {
  QStringList cells;
  const QTableWidget* table = view->table();
  for (int r = 0; r < table->rowCount(); ++r)
    for (int c = 0; c < table->columnCount(); ++c)
      cells << (table->item(r, c) ? table->item(r, c)->text() : QString());
  return cells.join(',');
}

// The next message box that opens (from the call that follows) is answered `button`;
// *asked says whether one opened.
void answerNextQuestion(QObject* context, QMessageBox::StandardButton button, bool* asked) {
  QTimer::singleShot(0, context, [button, asked] {
    if (auto* box = qobject_cast<QMessageBox*>(QApplication::activeModalWidget())) {
      *asked = true;
      QTest::mouseClick(box->button(button), Qt::LeftButton);
    }
  });
}

bool waitForFigures(Document* document) {
  return QTest::qWaitFor(
      [&] { return !document->isAnalysing() && !document->isLoading() && document->analysis() != nullptr; }, 60000);
}

} // namespace

class TestEditor : public QObject {
  Q_OBJECT

  // A shown window with the sample imported and its figures computed.
  std::unique_ptr<MainWindow> openSample() {
    auto window = std::make_unique<MainWindow>();
    window->resize(1500, 950);
    window->show();
    window->activateWindow(); // shortcuts need the active window
    if (!QTest::qWaitForWindowActive(window.get()))
      return nullptr;
    QSignalSpy spy(window.get(), &MainWindow::importFinished);
    window->importFileWithUnit(MLOD_SAMPLE, 2.54 / 0.45);
    if (!spy.wait(60000) || !spy.first()[0].toBool())
      return nullptr;
    if (!waitForFigures(window->document()))
      return nullptr;
    return window;
  }

  // A window shortcut: the window is made active first (on the offscreen platform nothing
  // gives activation back once another window had it, and shortcuts need it).
  static void press(MainWindow& window, Qt::Key key, Qt::KeyboardModifiers modifiers = {}) {
    if (QApplication::activeWindow() != &window) {
      window.activateWindow();
      QVERIFY(QTest::qWaitForWindowActive(&window));
      if (QApplication::activeWindow() != &window) // offscreen, after a modal box: the window's handle is
        QApplication::setActiveWindow(&window);    // active but the application was not told
    }
    QTest::keyClick(&window, key, modifiers);
  }

  int jointIndex(MainWindow& window, const char* name) {
    return window.document()->currentAssetPtr()->skeleton.find(name);
  }

  // Clicks a joint's row in the Skeleton dock.
  void clickJoint(MainWindow& window, int joint, Qt::KeyboardModifiers modifiers = {}) {
    QTreeView* view = window.skeletonView();
    const QModelIndex index = window.jointModel()->indexOfJoint(joint, JointTreeModel::NameColumn);
    view->scrollTo(index);
    QTest::mouseClick(view->viewport(), Qt::LeftButton, modifiers, view->visualRect(index).center());
  }

  // Edits a joint's threshold at the current level through the delegate's spin box.
  bool editThreshold(MainWindow& window, int joint, const QString& value) {
    QTreeView* view = window.skeletonView();
    const QModelIndex index = window.jointModel()->indexOfJoint(joint, JointTreeModel::ThresholdColumn);
    view->scrollTo(index);
    view->setFocus();
    // Keep a selection that holds the joint (a multi-joint edit); else select the joint.
    const bool selected = view->selectionModel()->isRowSelected(index.row(), index.parent());
    view->selectionModel()->setCurrentIndex(index, selected ? QItemSelectionModel::NoUpdate
                                                            : QItemSelectionModel::ClearAndSelect | QItemSelectionModel::Rows);
    QTest::keyClick(view, Qt::Key_F2);
    // The editor of this very cell: findChild() could return the last edit's editor, closed
    // but not deleted yet (deleteLater), and the value typed into it went nowhere.
    auto* editor = qobject_cast<QDoubleSpinBox*>(view->indexWidget(index));
    if (!editor)
      return false;
    editor->selectAll();
    QTest::keyClicks(editor, value);
    QTest::keyClick(editor, Qt::Key_Return);
    QCoreApplication::processEvents(); // the delegate commits on a queued call
    return true;
  }

  // Edits a cell of the LOD Levels dock through its delegate: F2, type, Return.
  bool editLevelCell(MainWindow& window, int level, int column, const QString& value) {
    QTableView* view = window.levelsView();
    const QModelIndex index = view->model()->index(level, column);
    view->setFocus();
    view->selectionModel()->setCurrentIndex(index, QItemSelectionModel::ClearAndSelect | QItemSelectionModel::Rows);
    QTest::keyClick(view, Qt::Key_F2);
    QWidget* editor = view->indexWidget(index);
    if (!editor)
      editor = QApplication::focusWidget();
    if (!editor || editor == view)
      return false;
    if (auto* box = qobject_cast<QDoubleSpinBox*>(editor))
      box->selectAll();
    else if (auto* line = qobject_cast<QLineEdit*>(editor))
      line->selectAll();
    QTest::keyClicks(editor, value);
    QTest::keyClick(editor, Qt::Key_Return);
    QCoreApplication::processEvents();
    return true;
  }

private slots:
  void initTestCase() {
    QCoreApplication::setOrganizationName("MotionLODEditorTest");
    QCoreApplication::setApplicationName("Motion LOD Studio Test");
  }
  void init() {
    Document scratch;
    Autosave(&scratch).discard(); // no test recovers what another left
  }

  // Importing a clip computes Table 1 at the project's four levels and fills every view.
  void importComputesFiguresAndViews() {
    auto window = openSample();
    QVERIFY(window);
    Document* document = window->document();
    QCOMPARE(document->analysis()->levelCount(), 5); // the original + the paper's four
    QCOMPARE(document->currentLevel(), 1);
    QCOMPARE(window->jointModel()->rowCount(), 1); // Hips
    QCOMPARE(window->statisticsView()->table()->columnCount(), 5); // one per level
    QCOMPARE(window->statisticsView()->table()->item(StatisticsView::SimplifiedRow, 0)->text(), QString("0.0"));
    QVERIFY(!window->statisticsView()->jointChart()->series().isEmpty());
    QVERIFY(!window->statisticsView()->frameChart()->series().isEmpty());
    QVERIFY(!window->statisticsView()->errorChart()->series().isEmpty());
    // Greedy is not monotone per joint, but the sample's clip-wide figure grows with E here.
    const auto& levels = document->analysis()->levels;
    QCOMPARE(levels[0].clusterCount, 0); // the original
    QVERIFY(levels[1].simplifiedPercent < levels[4].simplifiedPercent);
  }

  // Clicking a joint selects it everywhere: heat map, trajectory, status bar. On open the
  // views already show the joint with a child and the most clusters at the level in view
  // (the sample at LOD1, E = 5: Head, 58 clusters).
  void selectJointInTree() {
    auto window = openSample();
    QVERIFY(window);
    QCOMPARE(window->document()->currentJoint(), jointIndex(*window, "Head"));
    QVERIFY(window->clusteringView()->hasTable());
    const int leftUpLeg = jointIndex(*window, "LeftUpLeg");
    clickJoint(*window, leftUpLeg);
    QCOMPARE(window->document()->currentJoint(), leftUpLeg);
    QVERIFY(window->clusteringView()->hasTable());
    QVERIFY(window->statusText().contains("LeftUpLeg: T 5 cm·°"));
    window->trajectoryView()->repaint();
    QCOMPARE(window->trajectoryView()->pointCount(), 480);
  }

  // A threshold typed into the delegate changes the statistics and the heat map; one undo step.
  void editThresholdThroughDelegate() {
    auto window = openSample();
    QVERIFY(window);
    Document* document = window->document();
    const int joint = jointIndex(*window, "LeftUpLeg");
    clickJoint(*window, joint);
    window->clusteringView()->repaint();
    const QImage heatBefore = window->clusteringView()->renderedImage();
    const QString tableBefore = tableText(window->statisticsView());
    const double jointBefore = document->analysis()->levels[1].joints[std::size_t(joint)].simplifiedPercent;
    QVERIFY(editThreshold(*window, joint, "200"));
    QVERIFY(waitForFigures(document));
    QCOMPARE(document->undoStack()->count(), 2); // the import and this edit
    QVERIFY(document->project().assets[0].joints.count("LeftUpLeg"));
    QCOMPARE(*document->project().assets[0].joints.at("LeftUpLeg").thresholds[1], 200.0);
    QCOMPARE(document->analysis()->levels[1].joints[std::size_t(joint)].threshold, 200.0);
    QVERIFY(document->analysis()->levels[1].joints[std::size_t(joint)].simplifiedPercent > jointBefore);
    QVERIFY(tableText(window->statisticsView()) != tableBefore);
    window->clusteringView()->repaint();
    QVERIFY(window->clusteringView()->renderedImage() != heatBefore);
    // Only the touched joint at the touched level was clustered again, and the status says so.
    QCOMPARE(document->analysis()->clusteredPairs, 1);
    QVERIFY2(window->statusBar()->currentMessage().startsWith("1 joint clustering in "),
             qPrintable(window->statusBar()->currentMessage()));
  }

  // A cell editor shows its whole text: the threshold spin box of the Skeleton dock showed
  // "5.00 c" of "5.00 cm·°" (issue 26, item 7), its column being sized for the values alone.
  // Each spin box editor of the Skeleton and LOD Levels docks fits its text, suffix included.
  void cellEditorsFitTheirText() {
    QSettings().remove("mainWindow"); // the first run's layout
    auto window = openSample();
    QVERIFY(window);
    const auto fits = [](QWidget* editor, const QString& where) -> QString {
      auto* box = qobject_cast<QDoubleSpinBox*>(editor);
      if (!box)
        return where + ": no spin box editor";
      QLineEdit* line = box->findChild<QLineEdit*>();
      const QString text = line->text();
      const int needs = line->fontMetrics().horizontalAdvance(text);
      const QMargins margins = line->textMargins();
      const int room = line->contentsRect().width() - margins.left() - margins.right() - 4; // QLineEdit's 2 px a side
      if (!text.contains(box->suffix()) || needs > room)
        return QString("%1: '%2' needs %3 px, has %4 (editor %5 px)")
            .arg(where, text)
            .arg(needs)
            .arg(room)
            .arg(box->width());
      return {};
    };
    const int joint = jointIndex(*window, "LeftUpLeg");
    for (const int column : {int(JointTreeModel::ThresholdColumn), int(JointTreeModel::AlphaColumn)}) {
      QTreeView* view = window->skeletonView();
      const QModelIndex index = window->jointModel()->indexOfJoint(joint, column);
      view->scrollTo(index);
      view->setFocus();
      view->selectionModel()->setCurrentIndex(index, QItemSelectionModel::ClearAndSelect | QItemSelectionModel::Rows);
      QTest::keyClick(view, Qt::Key_F2);
      QWidget* editor = view->indexWidget(index);
      QVERIFY(editor);
      QTRY_VERIFY(editor->isVisible());
      const QString failure = fits(editor, QString("skeleton column %1").arg(column));
      QVERIFY2(failure.isEmpty(), qPrintable(failure));
      QVERIFY(editor->geometry().right() < view->viewport()->width()); // inside the view
      QTest::keyClick(editor, Qt::Key_Escape);
    }
    QTableView* levels = window->levelsView();
    for (const int column : {int(LevelsModel::ThresholdColumn), int(LevelsModel::SwitchDistanceColumn)}) {
      const QModelIndex index = levels->model()->index(1, column);
      levels->setFocus();
      levels->selectionModel()->setCurrentIndex(index, QItemSelectionModel::ClearAndSelect | QItemSelectionModel::Rows);
      QTest::keyClick(levels, Qt::Key_F2);
      QWidget* editor = levels->indexWidget(index);
      QVERIFY(editor);
      QTRY_VERIFY(editor->isVisible());
      const QString failure = fits(editor, QString("levels column %1").arg(column));
      QVERIFY2(failure.isEmpty(), qPrintable(failure));
      QTest::keyClick(editor, Qt::Key_Escape);
    }
  }

  // Undo and redo (by their shortcuts) restore the exact figures.
  void undoRedoRestoreExactFigures() {
    auto window = openSample();
    QVERIFY(window);
    Document* document = window->document();
    const Figures before = figuresOf(*document);
    const QString tableBefore = tableText(window->statisticsView());
    QVERIFY(editThreshold(*window, jointIndex(*window, "LowerBack"), "123"));
    QVERIFY(waitForFigures(document));
    const Figures after = figuresOf(*document);
    QVERIFY(after != before);
    press(*window, Qt::Key_Z, Qt::ControlModifier);
    QVERIFY(waitForFigures(document));
    QVERIFY(figuresOf(*document) == before);
    QCOMPARE(tableText(window->statisticsView()), tableBefore);
    press(*window, Qt::Key_Z, Qt::ControlModifier | Qt::ShiftModifier);
    QVERIFY(waitForFigures(document));
    QVERIFY(figuresOf(*document) == after);
  }

  // Stepping the alpha spin box is a slider drag: many edits, one undo step.
  void alphaStepsMergeIntoOneUndoStep() {
    auto window = openSample();
    QVERIFY(window);
    Document* document = window->document();
    const Figures before = figuresOf(*document);
    const int steps = document->undoStack()->count();
    QDoubleSpinBox* alpha = window->alphaBox();
    alpha->setFocus();
    for (int i = 0; i < 4; ++i)
      QTest::keyClick(alpha, Qt::Key_Up);
    QCOMPARE(document->project().alpha, 7.0);
    QCOMPARE(document->undoStack()->count(), steps + 1);
    QVERIFY(waitForFigures(document));
    QVERIFY(figuresOf(*document) != before);
    document->undoStack()->undo();
    QCOMPARE(document->project().alpha, 5.0);
    QCOMPARE(alpha->value(), 5.0);
    QVERIFY(waitForFigures(document));
    QVERIFY(figuresOf(*document) == before);
  }

  // The lock check box freezes nothing: a locked joint has no clusters; Ctrl+L unlocks.
  void lockJoint() {
    auto window = openSample();
    QVERIFY(window);
    Document* document = window->document();
    const int joint = jointIndex(*window, "Spine");
    clickJoint(*window, joint);
    QVERIFY(document->analysis()->levels[4].joints[std::size_t(joint)].clusters > 0);
    QTreeView* view = window->skeletonView();
    const QModelIndex lock = window->jointModel()->indexOfJoint(joint, JointTreeModel::LockColumn);
    view->scrollTo(lock);
    // The check indicator sits at the cell's left; a click there toggles it.
    const QRect cell = view->visualRect(lock);
    QTest::mouseClick(view->viewport(), Qt::LeftButton, {}, QPoint(cell.left() + 10, cell.center().y()));
    QVERIFY(waitForFigures(document));
    QVERIFY(document->project().assets[0].joints.count("Spine") && document->project().assets[0].joints.at("Spine").locked);
    QCOMPARE(document->analysis()->clusteredPairs, 0); // a locked joint is not clustered: nothing to do
    QCOMPARE(document->analysis()->reusedFromOtherLevels, 0);
    QVERIFY2(window->statusBar()->currentMessage().startsWith("no joint clustered again ("),
             qPrintable(window->statusBar()->currentMessage()));
    for (const JpcLevelResult& level : document->analysis()->levels) {
      QVERIFY(level.joints[std::size_t(joint)].locked);
      QCOMPARE(level.joints[std::size_t(joint)].clusters, 0);
    }
    QCOMPARE(lock.data(Qt::CheckStateRole).toInt(), int(Qt::Checked));
    press(*window, Qt::Key_L, Qt::ControlModifier);
    QVERIFY(waitForFigures(document));
    QVERIFY(!document->project().assets[0].joints.count("Spine"));
    QVERIFY(document->analysis()->levels[4].joints[std::size_t(joint)].clusters > 0);
  }

  // Issue 14: the mesh importance of a character's joints is reached by selecting the
  // character in the Assets dock; the Skeleton dock then lists its joints (not the first
  // asset's), the "Mesh x" edit is one undo step on the character's joint settings, it
  // survives save and reopen, and the character's JPC settings (what LOD generation reads)
  // carry it.
  void characterMeshImportanceFromTheAssetsDock() {
    auto window = openSample();
    QVERIFY(window);
    Document* document = window->document();
    QSignalSpy spy(window.get(), &MainWindow::importFinished);
    window->importFileWithUnit(QString(MLOD_ASSIMP_MODELS) + "/X/BCN_Epileptic.X", 0.0);
    QVERIFY(spy.wait(60000));
    QCOMPARE(document->assetCount(), 2);
    auto* tree = window->findChild<QTreeView*>("assetTree");
    QVERIFY(tree);
    tree->setCurrentIndex(window->assetModel()->index(0, 0)); // the motion first
    QCOMPARE(document->currentAsset(), 0);
    tree->setCurrentIndex(window->assetModel()->index(1, 0)); // then the character
    QCOMPARE(document->currentAsset(), 1);
    QVERIFY(waitForFigures(document));
    const Skeleton& character = document->asset(1)->skeleton;
    const int head = character.find("B_Jaw"); // a joint the sample motion does not have
    QVERIFY(head >= 0);
    QCOMPARE(document->asset(0)->skeleton.find("B_Jaw"), -1);
    const QModelIndex cell = window->jointModel()->indexOfJoint(head, JointTreeModel::ImportanceColumn);
    QVERIFY(cell.isValid());
    QCOMPARE(window->jointModel()->indexOfJoint(head, JointTreeModel::NameColumn).data().toString(), QString("B_Jaw"));
    QVERIFY(cell.flags() & Qt::ItemIsEditable);
    QCOMPARE(window->skeletonView()->model(), window->jointModel());
    QVERIFY(!window->skeletonView()->isColumnHidden(JointTreeModel::ImportanceColumn));
    const int steps = document->undoStack()->count();
    QVERIFY(window->jointModel()->setData(cell, 3.0, Qt::EditRole));
    QCOMPARE(document->undoStack()->count(), steps + 1);
    QCOMPARE(document->project().assets[1].joints.at("B_Jaw").meshImportance, 3.0);
    QVERIFY(!document->project().assets[0].joints.count("B_Jaw"));
    QCOMPARE(document->project().jpcSettings(1, document->asset(1)->unitScale).meshImportanceFor("B_Jaw"), 3.0);
    document->undoStack()->undo();
    QVERIFY(!document->project().assets[1].joints.count("B_Jaw"));
    document->undoStack()->redo();
    QCOMPARE(cell.data(Qt::EditRole).toDouble(), 3.0);
    QTemporaryDir dir;
    QVERIFY(window->saveProject(dir.filePath("importance.mlod")));
    MainWindow reopened;
    QSignalSpy opened(reopened.document(), &Document::projectOpened);
    QVERIFY(reopened.openProject(dir.filePath("importance.mlod")));
    QVERIFY(opened.wait(60000));
    QCOMPARE(reopened.document()->project().assets[1].joints.at("B_Jaw").meshImportance, 3.0);
  }

  // The Skeleton dock's mesh importance column: an edit is one undo step saved in the
  // project's joint settings, another joint's edit keeps it, undo takes it back.
  void meshImportanceIsAnUndoableJointSetting() {
    auto window = openSample();
    QVERIFY(window);
    Document* document = window->document();
    const int head = jointIndex(*window, "Head");
    const QModelIndex cell = window->jointModel()->indexOfJoint(head, JointTreeModel::ImportanceColumn);
    QCOMPARE(cell.data(Qt::EditRole).toDouble(), 1.0);
    const int steps = document->undoStack()->count();
    QVERIFY(window->jointModel()->setData(cell, 4.0, Qt::EditRole));
    QCOMPARE(document->undoStack()->count(), steps + 1);
    QCOMPARE(document->project().assets[0].joints.at("Head").meshImportance, 4.0);
    QCOMPARE(document->project().jpcSettings(0, 1.0).meshImportanceFor("Head"), 4.0);
    QVERIFY(cell.data(Qt::FontRole).value<QFont>().bold());
    QVERIFY(!window->jointModel()->setData(cell, 0.0, Qt::EditRole)); // importance must be > 0
    edit::setJointAlpha(*document, {jointIndex(*window, "Spine")}, 2.0);
    QCOMPARE(document->project().assets[0].joints.at("Head").meshImportance, 4.0);
    document->undoStack()->undo();
    document->undoStack()->undo();
    QVERIFY(!document->project().assets[0].joints.count("Head"));
    QCOMPARE(cell.data(Qt::EditRole).toDouble(), 1.0);
  }

  // With two joints selected (Ctrl+click), one edit sets both.
  void multiSelectEditsEveryJoint() {
    auto window = openSample();
    QVERIFY(window);
    Document* document = window->document();
    const int leftLeg = jointIndex(*window, "LeftLeg");
    const int rightLeg = jointIndex(*window, "RightLeg");
    clickJoint(*window, leftLeg);
    clickJoint(*window, rightLeg, Qt::ControlModifier);
    QCOMPARE(window->skeletonView()->selectionModel()->selectedRows().size(), 2);
    QVERIFY(editThreshold(*window, rightLeg, "77"));
    QVERIFY(waitForFigures(document));
    const auto& joints = document->project().assets[0].joints;
    QVERIFY(joints.count("LeftLeg") && joints.count("RightLeg"));
    QCOMPARE(*joints.at("LeftLeg").thresholds[1], 77.0);
    QCOMPARE(*joints.at("RightLeg").thresholds[1], 77.0);
    QCOMPARE(document->undoStack()->count(), 2);
  }

  // "Apply to children" copies a joint's settings down its chain in one undo step.
  void applyToChildren() {
    auto window = openSample();
    QVERIFY(window);
    Document* document = window->document();
    const int joint = jointIndex(*window, "LeftUpLeg");
    QVERIFY(editThreshold(*window, joint, "60"));
    clickJoint(*window, joint);
    press(*window, Qt::Key_C, Qt::ControlModifier | Qt::ShiftModifier);
    QVERIFY(waitForFigures(document));
    const auto& joints = document->project().assets[0].joints;
    for (const char* name : {"LeftLeg", "LeftFoot", "LeftToeBase"}) {
      QVERIFY(joints.count(name));
      QCOMPARE(*joints.at(name).thresholds[1], 60.0);
    }
    QCOMPARE(document->undoStack()->count(), 3);
    document->undoStack()->undo();
    QVERIFY(!document->project().assets[0].joints.count("LeftLeg"));
  }

  // The + and − buttons add and remove a level; every view follows; undo restores.
  void addAndRemoveLevel() {
    auto window = openSample();
    QVERIFY(window);
    Document* document = window->document();
    const Figures before = figuresOf(*document);
    auto* add = window->findChild<QToolButton*>("addLevelButton");
    auto* remove = window->findChild<QToolButton*>("removeLevelButton");
    QVERIFY(add && remove);
    QTest::mouseClick(add, Qt::LeftButton);
    QVERIFY(waitForFigures(document));
    QCOMPARE(document->lods().levels.back().motionThreshold, 600.0);
    QCOMPARE(document->lods().levels.back().name, std::string("LOD5"));
    QCOMPARE(document->analysis()->levelCount(), 6);
    QCOMPARE(window->statisticsView()->table()->columnCount(), 6);
    QCOMPARE(window->levelsView()->model()->rowCount(), 6);
    QCOMPARE(document->analysis()->clusteredPairs, document->analysis()->prepared->clusterableCount());
    // Remove level 1 (current), then undo both.
    QTest::mouseClick(remove, Qt::LeftButton);
    QVERIFY(waitForFigures(document));
    QCOMPARE(levelThresholdsFor(document->project(), document->currentAsset()),
             (std::vector<double>{0, 50, 100, 300, 600}));
    // The original cannot go.
    document->setCurrentLevel(0);
    QTest::mouseClick(remove, Qt::LeftButton);
    QCOMPARE(document->levelCount(), 5);
    QCOMPARE(document->undoStack()->count(), 3);
    document->undoStack()->undo();
    document->undoStack()->undo();
    QVERIFY(waitForFigures(document));
    QVERIFY(figuresOf(*document) == before);
  }

  // Each character owns its LOD set (issue 26, item 2: levels made for one character were
  // offered for another): level edits with one asset in view change that asset's levels
  // alone, the other keeps the project's; the Levels dock, the figures and the package follow
  // the asset in view; saved and reopened each keeps its own; undo gives the shared set back.
  void eachCharacterOwnsItsLevels() {
    auto window = openSample();
    QVERIFY(window);
    Document* document = window->document();
    QSignalSpy imported(window.get(), &MainWindow::importFinished);
    window->importFileWithUnit(QString(MLOD_ASSIMP_MODELS) + "/X/BCN_Epileptic.X", 100.0);
    QVERIFY(imported.wait(60000));
    document->setCurrentAsset(1);
    QVERIFY(waitForFigures(document));
    const LodSet shared = document->project().lods;
    QCOMPARE(int(shared.levels.size()), 5);
    QVERIFY(edit::setLevelMeshRatio(*document, 3, 0.1));
    QVERIFY(edit::removeLevel(*document, 4));
    QVERIFY(waitForFigures(document));
    QCOMPARE(document->levelCount(), 4);
    QCOMPARE(document->lods().levels[3].meshRatio, 0.1);
    QCOMPARE(window->levelsView()->model()->rowCount(), 4);
    QCOMPARE(document->analysis()->levelCount(), 4);
    QVERIFY(document->project().assets[1].lods);
    QVERIFY(document->project().lods == shared);
    const std::vector<const Asset*> imports = document->importedAssets();
    QCOMPARE(packagePlan(document->project(), imports, 1).levels, 4);
    QCOMPARE(packagePlan(document->project(), imports, 0).levels, 5);
    // the sample keeps the project's set
    document->setCurrentAsset(0);
    QVERIFY(waitForFigures(document));
    QVERIFY(!document->project().assets[0].lods);
    QCOMPARE(document->levelCount(), 5);
    QCOMPARE(window->levelsView()->model()->rowCount(), 5);
    QCOMPARE(document->analysis()->levelCount(), 5);
    document->setCurrentLevel(4);
    QCOMPARE(document->currentLevel(), 4);
    // back on BCN: its level 4 is gone, the view shows one it has
    document->setCurrentAsset(1);
    QCOMPARE(document->currentLevel(), 3);
    // saved and reopened: each its own
    QTemporaryDir dir;
    const QString path = dir.filePath("two.mlod");
    QVERIFY(window->saveProject(path));
    {
      MainWindow reopened;
      reopened.show();
      QSignalSpy opened(reopened.document(), &Document::projectOpened);
      QVERIFY(reopened.openProject(path));
      QVERIFY(opened.wait(60000));
      QVERIFY(lodSetFor(reopened.document()->project(), 1) == *document->project().assets[1].lods);
      QVERIFY(lodSetFor(reopened.document()->project(), 0) == shared);
    }
    // The sample mapped onto BCN plays with BCN's levels (issue 26, item 7: it kept its own),
    // in view when it is assigned as when it is chosen again: levels dock, figures, viewport.
    document->setCurrentLevel(4);
    QVERIFY(edit::assignMotion(*document, 0, 1));
    QVERIFY(waitForFigures(document));
    QVERIFY(document->lods() == *document->project().assets[1].lods);
    QCOMPARE(document->levelCount(), 4);
    QCOMPARE(document->currentLevel(), 3);
    QCOMPARE(window->levelsView()->model()->rowCount(), 4);
    QTRY_COMPARE(document->analysis()->levelCount(), 4);
    QVERIFY(!document->project().assets[0].lods);
    // a level edit with the motion in view edits the character's set, and the figures follow
    QVERIFY(edit::setLevelThreshold(*document, 3, 77.0));
    QVERIFY(waitForFigures(document));
    QCOMPARE(document->project().assets[1].lods->levels[3].motionThreshold, 77.0);
    QVERIFY(document->project().lods == shared);
    QTRY_COMPARE(document->analysis()->levels[3].threshold, 77.0);
    document->setCurrentAsset(1);
    document->setCurrentAsset(0);
    QVERIFY(waitForFigures(document));
    QCOMPARE(document->analysis()->levels[3].threshold, 77.0);
    document->undoStack()->undo(); // the threshold
    document->undoStack()->undo(); // the assignment: the sample's own levels again
    QVERIFY(waitForFigures(document));
    QCOMPARE(document->levelCount(), 5);
    QTRY_COMPARE(document->analysis()->levelCount(), 5);
    // undo both: BCN plays with the project's set again
    document->undoStack()->undo();
    document->undoStack()->undo();
    QVERIFY(!document->project().assets[1].lods);
    QCOMPARE(document->levelCount(), 5);
  }

  // Issue 26's last item: a motion assigned to two characters plays with the set of the one
  // it is viewed on. The sample is mapped onto BCN_Epileptic (4 levels of its own) and
  // Testwuson (3 of its own); choosing the character in the viewport's box changes what the
  // LOD Levels dock shows and names, the figures, the Budget dialog's and the Export dialog's
  // character, and where a level edit lands; back on its own skeleton, the first mapping's.
  void viewedCharacterPicksTheLodSet() {
    auto window = openSample();
    QVERIFY(window);
    Document* document = window->document();
    for (const auto& [file, unit] :
         {std::pair{QString("/X/BCN_Epileptic.X"), 100.0}, {QString("/X/Testwuson.X"), 0.0}}) {
      QSignalSpy imported(window.get(), &MainWindow::importFinished);
      window->importFileWithUnit(QString(MLOD_ASSIMP_MODELS) + file, unit);
      QVERIFY(imported.wait(60000));
    }
    QCOMPARE(document->assetCount(), 3);
    document->setCurrentAsset(1); // BCN: 4 levels of its own
    QVERIFY(edit::removeLevel(*document, 4));
    document->setCurrentAsset(2); // Testwuson: 3 of its own
    QVERIFY(edit::removeLevel(*document, 4));
    QVERIFY(edit::removeLevel(*document, 3));
    QVERIFY(edit::assignMotion(*document, 0, 1));
    QString warning; // a biped clip on a quadruped: assigned, with a warning
    QVERIFY(edit::assignMotion(*document, 0, 2, nullptr, &warning));
    document->setCurrentAsset(0);
    QVERIFY(waitForFigures(document));
    QDockWidget* levelsDock = window->findChild<QDockWidget*>("levelsDock");
    QVERIFY(levelsDock);
    // on its own skeleton: the first mapping's character, BCN
    QComboBox* box = window->viewportPanel()->characterBox();
    QCOMPARE(box->count(), 3);
    QCOMPARE(box->currentIndex(), 0);
    QCOMPARE(document->viewedCharacter(), -1);
    QCOMPARE(window->levelsView()->model()->rowCount(), 4);
    QCOMPARE(levelsDock->windowTitle(), QString("LOD Levels — BCN_Epileptic.X"));
    const auto exportCharacter = [&] {
      PluginHost host;
      ExportDialog dialog(document, &host);
      const auto* label = dialog.findChild<QLabel*>("assetLabel");
      const auto* levels = dialog.findChild<QListWidget*>("levelsList");
      return label->text() + QString(" %1 levels").arg(levels->count());
    };
    QCOMPARE(exportCharacter(), QString("Character: <b>BCN_Epileptic.X</b> 4 levels"));

    // viewed on Testwuson: its 3 levels everywhere
    box->setCurrentIndex(2);
    QCOMPARE(box->currentText(), QString("Testwuson.X"));
    QCOMPARE(document->viewedCharacter(), 2);
    QVERIFY(document->lods() == *document->project().assets[2].lods);
    QCOMPARE(window->levelsView()->model()->rowCount(), 3);
    QCOMPARE(levelsDock->windowTitle(), QString("LOD Levels — Testwuson.X"));
    QTRY_COMPARE(document->analysis()->levelCount(), 3);
    QCOMPARE(exportCharacter(), QString("Character: <b>Testwuson.X</b> 3 levels"));
    {
      BudgetDialog* budget = window->openBudgetDialog();
      QVERIFY(budget);
      QVERIFY2(budget->characterLabel()->text().contains("Testwuson.X"), qPrintable(budget->characterLabel()->text()));
      budget->reject();
    }
    // a level edit lands in Testwuson's set, not BCN's
    const LodSet bcn = *document->project().assets[1].lods;
    QVERIFY(edit::setLevelThreshold(*document, 1, 33.0));
    QCOMPARE(document->project().assets[2].lods->levels[1].motionThreshold, 33.0);
    QVERIFY(*document->project().assets[1].lods == bcn);
    QVERIFY(waitForFigures(document));
    QTRY_COMPARE(document->analysis()->levels[1].threshold, 33.0);

    // back on BCN, then on its own skeleton (the first mapping's, BCN)
    box->setCurrentIndex(1);
    QCOMPARE(document->viewedCharacter(), 1);
    QCOMPARE(window->levelsView()->model()->rowCount(), 4);
    QCOMPARE(exportCharacter(), QString("Character: <b>BCN_Epileptic.X</b> 4 levels"));
    box->setCurrentIndex(2);
    box->setCurrentIndex(0);
    QCOMPARE(document->viewedCharacter(), -1);
    QCOMPARE(window->levelsView()->model()->rowCount(), 4);
    // the view follows the document: set there, the box shows it; another asset clears it
    document->setViewedCharacter(2);
    QCOMPARE(box->currentIndex(), 2);
    document->setViewedCharacter(0); // not a character the motion is mapped onto: refused
    QCOMPARE(document->viewedCharacter(), -1);
    document->setViewedCharacter(2);
    document->setCurrentAsset(1);
    QCOMPARE(document->viewedCharacter(), -1);
    document->setCurrentAsset(0);
    QCOMPARE(box->currentIndex(), 0);
    // the mapping viewed goes: viewed on none again
    box->setCurrentIndex(2);
    edit::unassignMotion(*document, 1);
    QCOMPARE(document->viewedCharacter(), -1);
    QCOMPARE(box->count(), 2);
    QCOMPARE(window->levelsView()->model()->rowCount(), 4);
  }

  // Moving a level carries the joints' overrides for it along.
  void moveLevelCarriesOverrides() {
    auto window = openSample();
    QVERIFY(window);
    Document* document = window->document();
    document->setCurrentLevel(2);
    QVERIFY(editThreshold(*window, jointIndex(*window, "Neck"), "11"));
    QTest::mouseClick(window->findChild<QToolButton*>("levelDownButton"), Qt::LeftButton);
    QVERIFY(waitForFigures(document));
    QCOMPARE(levelThresholdsFor(document->project(), document->currentAsset()),
             (std::vector<double>{0, 5, 100, 50, 300}));
    // New figures (levels 2 and 3 swapped), none clustered: the status says they came from
    // the cache rather than that nothing was clustered again.
    QCOMPARE(document->analysis()->clusteredPairs, 0);
    QVERIFY(document->analysis()->reusedFromOtherLevels > 0);
    QVERIFY2(window->statusBar()->currentMessage().startsWith("figures from the cache: "),
             qPrintable(window->statusBar()->currentMessage()));
    QVERIFY(document->project().assets[0].joints.count("Neck"));
    const auto& neck = document->project().assets[0].joints.at("Neck").thresholds;
    QCOMPARE(neck.size(), std::size_t(4));
    QVERIFY(!neck[2]);
    QCOMPARE(*neck[3], 11.0);
    // The original stays first: level 1 cannot move up.
    document->setCurrentLevel(1);
    QTest::mouseClick(window->findChild<QToolButton*>("levelUpButton"), Qt::LeftButton);
    QCOMPARE(levelThresholdsFor(document->project(), document->currentAsset()),
             (std::vector<double>{0, 5, 100, 50, 300}));
  }

  // The LOD Levels dock edits name, threshold, mesh ratio and switch distance in place;
  // each edit is one undo step; the original level keeps its figures; a switch distance out
  // of order is refused with a reason in the log; everything survives save and reopen.
  void levelsDockEditsEveryField() {
    QTemporaryDir dir;
    const QString path = dir.filePath("levels.mlod");
    LodSet edited;
    {
      auto window = openSample();
      QVERIFY(window);
      Document* document = window->document();
      const int steps = document->undoStack()->count();
      QAbstractItemModel* model = window->levelsView()->model();
      QCOMPARE(model->columnCount(), int(LevelsModel::ColumnCount));
      QVERIFY(editLevelCell(*window, 2, LevelsModel::NameColumn, "Crowd"));
      QCOMPARE(document->lods().levels[2].name, std::string("Crowd"));
      QCOMPARE(model->index(2, LevelsModel::NameColumn).data().toString(), QString("Crowd"));
      QVERIFY(editLevelCell(*window, 2, LevelsModel::MeshRatioColumn, "0.4"));
      QCOMPARE(document->lods().levels[2].meshRatio, 0.4);
      QVERIFY(editLevelCell(*window, 1, LevelsModel::SwitchDistanceColumn, "800"));
      QVERIFY(editLevelCell(*window, 2, LevelsModel::SwitchDistanceColumn, "1500"));
      QCOMPARE(document->lods().levels[2].switchDistanceCm, 1500.0);
      QCOMPARE(document->lods().levels[4].switchDistanceCm, 1500.0); // kept in order
      QCOMPARE(document->lods().levels[1].switchDistanceCm, 800.0);
      // one format a column (issue 26: "72.0976 m" beside "0 m", "9.968%")
      QCOMPARE(model->index(2, LevelsModel::MeshRatioColumn).data().toString(), QString("40.0%"));
      QCOMPARE(model->index(2, LevelsModel::SwitchDistanceColumn).data().toString(), QString("15.00 m"));
      QCOMPARE(model->index(0, LevelsModel::SwitchDistanceColumn).data().toString(), QString("0.00 m"));
      QCOMPARE(model->index(0, LevelsModel::MeshRatioColumn).data().toString(), QString("100.0%"));
      QVERIFY(editLevelCell(*window, 2, LevelsModel::ThresholdColumn, "70"));
      QVERIFY(waitForFigures(document));
      QCOMPARE(document->lods().levels[2].motionThreshold, 70.0);
      QCOMPARE(document->analysis()->levels[2].threshold, 70.0);
      QCOMPARE(document->undoStack()->count(), steps + 5);
      // Refused: a name in use, a distance nearer than the previous level's; nothing pushed.
      QVERIFY(editLevelCell(*window, 3, LevelsModel::NameColumn, "Crowd"));
      QVERIFY(editLevelCell(*window, 3, LevelsModel::SwitchDistanceColumn, "100"));
      QCOMPARE(document->undoStack()->count(), steps + 5);
      QCOMPARE(document->lods().levels[3].name, std::string("LOD3"));
      QVERIFY(window->logText().contains("already named"));
      QVERIFY(window->logText().contains("at least the previous level's"));
      // The original: only its name is editable.
      QVERIFY(!(model->flags(model->index(0, LevelsModel::ThresholdColumn)) & Qt::ItemIsEditable));
      QVERIFY(!(model->flags(model->index(0, LevelsModel::MeshRatioColumn)) & Qt::ItemIsEditable));
      QVERIFY(model->flags(model->index(0, LevelsModel::NameColumn)) & Qt::ItemIsEditable);
      QVERIFY(!document->lods().validate()); // no error
      // Undo the threshold: the figures come back.
      document->undoStack()->undo();
      QVERIFY(waitForFigures(document));
      QCOMPARE(document->analysis()->levels[2].threshold, 50.0);
      document->undoStack()->redo();
      QVERIFY(waitForFigures(document));
      edited = document->lods();
      QVERIFY(window->saveProject(path));
      window->close();
    }
    MainWindow reopened;
    reopened.show();
    QSignalSpy opened(reopened.document(), &Document::projectOpened);
    QVERIFY(reopened.openProject(path));
    QVERIFY(opened.wait(60000));
    QVERIFY(reopened.document()->lods() == edited);
    QCOMPARE(reopened.levelsView()->model()->index(2, LevelsModel::NameColumn).data().toString(), QString("Crowd"));
  }

  // PgDown shows the next level in every view.
  void levelShortcutMovesEveryView() {
    auto window = openSample();
    QVERIFY(window);
    Document* document = window->document();
    clickJoint(*window, jointIndex(*window, "LeftUpLeg"));
    press(*window, Qt::Key_PageDown);
    press(*window, Qt::Key_PageDown);
    QCOMPARE(document->currentLevel(), 3);
    QCOMPARE(window->levelsView()->currentIndex().row(), 3);
    QCOMPARE(window->jointModel()->headerData(JointTreeModel::ThresholdColumn, Qt::Horizontal).toString(),
             QString("T L3\n(cm·°)"));
    QVERIFY(window->statusText().contains("L3 LOD3 · E = 100"));
    QVERIFY(window->statusText().contains("LeftUpLeg: T 100 cm·°"));
    QVERIFY(window->statisticsView()->table()->item(0, 3)->font().bold());
  }

  // Wheel zooms the heat map about the cursor; hover reads the table entry exactly.
  void heatMapZoomsAndReadsEntries() {
    auto window = openSample();
    QVERIFY(window);
    const int joint = jointIndex(*window, "LeftUpLeg");
    clickJoint(*window, joint);
    ClusteringTableView* view = window->clusteringView();
    QCOMPARE(view->visibleFrames(), 480.0);
    const QPoint centre(48 + 60, 8 + 60);
    QWheelEvent wheel(centre, view->mapToGlobal(centre), {}, QPoint(0, 120), Qt::NoButton, Qt::NoModifier,
                      Qt::NoScrollPhase, false);
    QApplication::sendEvent(view, &wheel);
    QVERIFY(view->visibleFrames() < 480.0);
    const auto entry = view->entryAt(centre);
    QVERIFY(entry.has_value());
    const JointTrack& track = window->document()->analysis()->prepared->track(joint);
    QCOMPARE(entry->error, track.error(entry->t, entry->ref));
    QTest::mouseClick(view, Qt::RightButton, {}, centre); // right click resets the zoom
    QCOMPARE(view->visibleFrames(), 480.0);
    // The colour scale beside the table runs to the largest E in view (cm·°); a wheel event
    // without a vertical or horizontal step (a touchpad's phase) zooms neither way.
    view->grab();
    QVERIFY(view->scaleMaximum() >= entry->error);
    QVERIFY(view->scaleMaximum() > 0.0);
    QWheelEvent still(centre, view->mapToGlobal(centre), {}, QPoint(0, 0), Qt::NoButton, Qt::NoModifier,
                      Qt::ScrollUpdate, false);
    QApplication::sendEvent(view, &still);
    QCOMPARE(view->visibleFrames(), 480.0);
  }

  // The sample (a CMU skeleton), Testwuson and BCN_Epileptic, with their units.
  static QList<QPair<QString, double>> firstRunFiles() {
    return {{MLOD_SAMPLE, 2.54 / 0.45},
            {QString(MLOD_ASSIMP_MODELS) + "/X/Testwuson.X", 0.0},
            {QString(MLOD_ASSIMP_MODELS) + "/X/BCN_Epileptic.X", 0.0}};
  }
  // `window` at the first run's size, shown, with `file` imported and its figures computed.
  static bool showImported(MainWindow& window, const QString& file, double unit) {
    window.resize(1600, 1000);
    window.show();
    if (!QTest::qWaitForWindowExposed(&window))
      return false;
    QSignalSpy imported(&window, &MainWindow::importFinished);
    window.importFileWithUnit(file, unit);
    return imported.wait(60000) && imported.first()[0].toBool() && waitForFigures(window.document());
  }

  // The per-joint chart names its joints readably (issue 26, item 7: every label was "⋮", a
  // rotated "…", at 38 and 54 clusterable joints): the labels shown are joint names, whole or
  // cut after at least three characters, thinned to one every jointLabelStep() bars where a
  // name each would not fit, and most of them whole; for the sample (a CMU skeleton),
  // Testwuson and BCN_Epileptic, in the window's first layout.
  void perJointChartNamesItsJoints() {
    QSettings().remove("mainWindow"); // the first run's layout
    for (const auto& [file, unit] : firstRunFiles()) {
      MainWindow window;
      QVERIFY(showImported(window, file, unit));
      StatisticsView* statistics = window.statisticsView();
      const QStringList names = statistics->jointNames();
      QVERIFY2(names.size() >= 30, qPrintable(QString::number(names.size())));
      QChart* chart = statistics->jointChart();
      // the labels the chart shows: its rotated text items below the plot
      const auto shown = [&] {
        QStringList out;
        for (QGraphicsItem* item : chart->scene()->items())
          if (auto* text = dynamic_cast<QGraphicsTextItem*>(item);
              text && text->isVisible() && text->rotation() != 0.0 && !text->toPlainText().isEmpty() &&
              text->mapToScene(text->boundingRect().center()).y() > chart->plotArea().bottom())
            out << text->toPlainText();
        return out;
      };
      QTRY_VERIFY(shown().size() >= 8);
      QVERIFY(mlod::test::settles([&] { return shown(); }));
      const QStringList labels = shown();
      int whole = 0;
      for (const QString& label : labels) {
        if (names.contains(label)) {
          ++whole;
          continue;
        }
        const QString cut = label.endsWith("...")           ? label.chopped(3)
                            : label.endsWith(QChar(0x2026)) ? label.chopped(1)
                                                            : QString();
        const bool prefix = cut.size() >= 3 && std::any_of(names.begin(), names.end(),
                                                           [&](const QString& n) { return n.startsWith(cut); });
        QVERIFY2(prefix, qPrintable(QString("%1: label '%2' is no joint's name").arg(file, label)));
      }
      const int step = statistics->jointLabelStep();
      QVERIFY2(labels.size() >= (names.size() + step - 1) / step - 1,
               qPrintable(QString("%1: %2 labels shown of %3 joints, one every %4")
                              .arg(file)
                              .arg(labels.size())
                              .arg(names.size())
                              .arg(step)));
      QVERIFY2(
          2 * whole >= labels.size(),
          qPrintable(
              QString("%1: %2 of %3 labels whole: %4").arg(file).arg(whole).arg(labels.size()).arg(labels.join(", "))));
    }
  }

  // The per-frame chart carries a playhead at the frame the 3D views show.
  void perFrameChartHasThePlayhead() {
    auto window = openSample();
    QVERIFY(window);
    StatisticsView* statistics = window->statisticsView();
    statistics->setPlayhead(120);
    QLineSeries* playhead = nullptr;
    for (QAbstractSeries* series : statistics->frameChart()->series())
      if (series->objectName() == "playhead")
        playhead = qobject_cast<QLineSeries*>(series);
    QVERIFY(playhead);
    QCOMPARE(playhead->count(), 2);
    QCOMPARE(playhead->at(0).x(), 120.0);
    QCOMPARE(playhead->at(1).x(), 120.0);
    QVERIFY(playhead->at(1).y() > playhead->at(0).y());
    statistics->setPlayhead(-1);
    QCOMPARE(playhead->count(), 0);
  }

  // The per-frame chart zooms with the wheel towards the frame under the cursor (that frame
  // stays under it), never below 10 frames; a right click shows the whole clip again.
  void perFrameChartZoomsTowardsTheCursor() {
    auto window = openSample();
    QVERIFY(window);
    StatisticsView* statistics = window->statisticsView();
    QTabWidget* tabs = statistics->findChild<QTabWidget*>();
    QVERIFY(tabs);
    tabs->setCurrentIndex(1); // Per frame
    QChart* chart = statistics->frameChart();
    QVERIFY(!chart->scene()->views().isEmpty());
    QGraphicsView* view = chart->scene()->views().first();
    QTRY_VERIFY(chart->plotArea().width() > 50.0);
    QCOMPARE(statistics->visibleFramesMin(), 0.0);
    QCOMPARE(statistics->visibleFramesMax(), 479.0);
    const QRectF plot = chart->plotArea();
    const QPoint at = view->mapFromScene(chart->mapToScene(QPointF(plot.left() + 0.75 * plot.width(), plot.center().y())));
    const auto wheel = [&](int delta) {
      QWheelEvent event(at, view->viewport()->mapToGlobal(at), {}, QPoint(0, delta), Qt::NoButton, Qt::NoModifier,
                        Qt::NoScrollPhase, false);
      QApplication::sendEvent(view->viewport(), &event);
    };
    const auto frameUnderCursor = [&] {
      const double x = (chart->mapFromScene(view->mapToScene(at)).x() - plot.left()) / plot.width();
      return statistics->visibleFramesMin() + x * (statistics->visibleFramesMax() - statistics->visibleFramesMin());
    };
    const double before = frameUnderCursor();
    QVERIFY(std::abs(before - 0.75 * 479.0) < 2.0);
    wheel(120);
    QVERIFY(std::abs((statistics->visibleFramesMax() - statistics->visibleFramesMin()) - 0.8 * 479.0) < 1e-6);
    QVERIFY(std::abs(frameUnderCursor() - before) < 1e-6);
    QVERIFY(statistics->visibleFramesMin() > 0.0);
    for (int step = 0; step < 40; ++step)
      wheel(120);
    QCOMPARE(statistics->visibleFramesMax() - statistics->visibleFramesMin(), 10.0);
    QVERIFY(std::abs(frameUnderCursor() - before) < 1e-6);
    wheel(-120 * 60); // out past the clip: the whole clip, no further
    QCOMPARE(statistics->visibleFramesMin(), 0.0);
    QCOMPARE(statistics->visibleFramesMax(), 479.0);
    wheel(240);
    QVERIFY(statistics->visibleFramesMax() - statistics->visibleFramesMin() < 479.0);
    QTest::mouseClick(view->viewport(), Qt::RightButton, {}, at);
    QCOMPARE(statistics->visibleFramesMin(), 0.0);
    QCOMPARE(statistics->visibleFramesMax(), 479.0);
  }

  // At the first run's size (1600 x 1000) and layout, the Skeleton dock shows every joint
  // name whole, the sample's and a character's with deep hands (BCN_Epileptic.X), and each
  // name's tooltip has it whole (the elision's fallback); no header text is cut and each figure
  // column's header explains itself in a tooltip; every LOD level is in sight without
  // scrolling. Before: names cut to "Lef…ase", "L…s", "Mesh ×" half hidden.
  void skeletonAndLevelsDocksAreReadable() {
    QSettings().remove("mainWindow"); // the first run's layout, whatever a test saved
    for (const auto& [file, unit] : firstRunFiles()) {
      MainWindow window;
      QVERIFY(showImported(window, file, unit));

      QTreeView* tree = window.skeletonView();
      QHeaderView* header = tree->header();
      QTableView* levels = window.levelsView();
      // the views lay out their rows and sections
      QVERIFY(mlod::test::settles([&] {
        QList<int> sizes{header->length(), tree->viewport()->width(), levels->viewport()->height()};
        for (int column = 0; column < JointTreeModel::ColumnCount; ++column)
          sizes << header->sectionSize(column);
        for (int row = 0; row < levels->model()->rowCount(); ++row)
          sizes << levels->rowViewportPosition(row);
        return sizes;
      }));
      QVERIFY2(
          header->length() <= tree->viewport()->width(),
          qPrintable(
              QString("%1: columns %2 px wide in %3").arg(file).arg(header->length()).arg(tree->viewport()->width())));
      const int textMargin = 2 * (tree->style()->pixelMetric(QStyle::PM_FocusFrameHMargin, nullptr, tree) + 1);
      int joints = 0;
      std::vector<QModelIndex> pending{tree->model()->index(0, 0)};
      while (!pending.empty()) {
        const QModelIndex index = pending.back();
        pending.pop_back();
        ++joints;
        const QString name = index.data().toString();
        QVERIFY2(index.data(Qt::ToolTipRole).toString().contains(name), qPrintable(name));
        const int room = tree->visualRect(index).width() - textMargin;
        QVERIFY2(tree->fontMetrics().horizontalAdvance(name) <= room,
                 qPrintable(QString("%1: %2 needs %3 px, has %4")
                                .arg(file, name)
                                .arg(tree->fontMetrics().horizontalAdvance(name))
                                .arg(room)));
        for (int row = 0; row < tree->model()->rowCount(index); ++row)
          pending.push_back(tree->model()->index(row, 0, index));
      }
      QCOMPARE(joints, window.document()->currentAssetPtr()->skeleton.jointCount());

      const QFontMetrics headerMetrics(header->font());
      const int headerMargin = 2 * header->style()->pixelMetric(QStyle::PM_HeaderMargin, nullptr, header);
      for (int column = 0; column < JointTreeModel::ColumnCount; ++column) {
        const QString text = tree->model()->headerData(column, Qt::Horizontal).toString();
        const QSize size = headerMetrics.size(0, text);
        QVERIFY2(size.width() + headerMargin <= header->sectionSize(column) && size.height() <= header->height(),
                 qPrintable(QString("'%1': %2 x %3 in %4 x %5")
                                .arg(text)
                                .arg(size.width() + headerMargin)
                                .arg(size.height())
                                .arg(header->sectionSize(column))
                                .arg(header->height())));
        QVERIFY2(!tree->model()->headerData(column, Qt::Horizontal, Qt::ToolTipRole).toString().isEmpty(),
                 qPrintable(text));
      }

      QVERIFY(levels->model()->rowCount() >= 5);
      for (int row = 0; row < levels->model()->rowCount(); ++row) {
        const QRect rect = levels->visualRect(levels->model()->index(row, 0));
        QVERIFY2(rect.top() >= 0 && rect.bottom() < levels->viewport()->height(),
                 qPrintable(QString("level %1: rows %2-%3 of %4 px")
                                .arg(row)
                                .arg(rect.top())
                                .arg(rect.bottom())
                                .arg(levels->viewport()->height())));
      }
    }
  }

  // Dragging rotates the trajectory sphere.
  void trajectoryRotatesOnDrag() {
    auto window = openSample();
    QVERIFY(window);
    clickJoint(*window, jointIndex(*window, "LeftForeArm"));
    TrajectoryView* view = window->trajectoryView();
    const double yaw = view->yaw();
    QTest::mousePress(view, Qt::LeftButton, {}, QPoint(50, 50));
    QMouseEvent move(QEvent::MouseMove, QPointF(90, 60), view->mapToGlobal(QPointF(90, 60)), Qt::NoButton,
                     Qt::LeftButton, Qt::NoModifier);
    QApplication::sendEvent(view, &move);
    QTest::mouseRelease(view, Qt::LeftButton, {}, QPoint(90, 60));
    QCOMPARE(view->yaw(), yaw + 20.0);
  }

  // Save, close, reopen: the same project and the same figures, to the bit.
  void saveCloseReopenIdenticalFigures() {
    QTemporaryDir dir;
    const QString path = dir.filePath("tuned.mlod");
    Figures saved;
    Project project;
    {
      auto window = openSample();
      QVERIFY(window);
      Document* document = window->document();
      QVERIFY(editThreshold(*window, jointIndex(*window, "LeftUpLeg"), "42"));
      edit::setJointAlpha(*document, {jointIndex(*window, "Head")}, 9.5);
      edit::setJointsLocked(*document, {jointIndex(*window, "Spine1")}, true);
      QVERIFY(waitForFigures(document));
      QVERIFY(window->saveProject(path));
      QVERIFY(!document->isModified());
      saved = figuresOf(*document);
      project = document->project();
      window->close();
    }
    QVERIFY(QFile::exists(path));
    MainWindow reopened;
    reopened.show();
    QSignalSpy opened(reopened.document(), &Document::projectOpened);
    QVERIFY(reopened.openProject(path));
    QVERIFY(opened.wait(60000));
    QCOMPARE(opened.first()[0].toBool(), true);
    QVERIFY(waitForFigures(reopened.document()));
    QVERIFY(reopened.document()->project() == project);
    QVERIFY(figuresOf(*reopened.document()) == saved);
    QCOMPARE(reopened.assetModel()->assetCount(), 1);
  }

  // A malformed or newer project is refused with a clear message; nothing is lost.
  void refuseMalformedProject() {
    auto window = openSample();
    QVERIFY(window);
    Document* document = window->document();
    QVERIFY(editThreshold(*window, jointIndex(*window, "Neck"), "33"));
    QVERIFY(waitForFigures(document));
    const Project before = document->project();
    const Figures figures = figuresOf(*document);
    QTemporaryDir dir;
    const auto write = [&](const QString& name, const QByteArray& bytes) {
      QFile file(dir.filePath(name));
      file.open(QIODevice::WriteOnly);
      file.write(bytes);
      return file.fileName();
    };
    const QString garbage = write("garbage.mlod", "{\"format\": \"motionlod-project\", \"version\": 1, \"alpha\": [}");
    QVERIFY(!window->openProject(garbage));
    QVERIFY(window->logText().contains("not valid JSON"));
    auto* box = window->findChild<QMessageBox*>("errorBox");
    QVERIFY(box && box->isVisible());
    box->close();
    const QString newer = write("newer.mlod", "{\"format\": \"motionlod-project\", \"version\": 99}");
    QVERIFY(!window->openProject(newer));
    QVERIFY(window->logText().contains("made by a newer Motion LOD Studio"));
    QVERIFY(document->project() == before);
    QVERIFY(figuresOf(*document) == figures);
    QCOMPARE(document->undoStack()->count(), 2); // nothing lost, undo included
  }

  // After a crash (no clean close) the autosave brings the edits back.
  void recoverFromAutosave() {
    Project lost;
    {
      auto window = openSample();
      QVERIFY(window);
      QVERIFY(editThreshold(*window, jointIndex(*window, "RightArm"), "250"));
      QVERIFY(waitForFigures(window->document()));
      QVERIFY(window->autosave()->saveNow());
      lost = window->document()->project();
      // No close(): the window goes away as in a crash and leaves the recovery file.
      window->hide();
    }
    MainWindow next;
    next.show();
    QVERIFY(next.autosave()->hasRecovery());
    QSignalSpy opened(next.document(), &Document::projectOpened);
    QVERIFY(next.offerRecovery(false));
    QVERIFY(opened.wait(60000));
    QVERIFY(waitForFigures(next.document()));
    QVERIFY(next.document()->project().assets.size() == 1 && next.document()->project().assets[0].joints.count("RightArm"));
    QCOMPARE(*next.document()->project().assets[0].joints.at("RightArm").thresholds[1], 250.0);
    QVERIFY(next.document()->lods() == lodSetFor(lost, lost.view.asset));
    QVERIFY(next.document()->isModified());
    QVERIFY(next.document()->fileName().isEmpty());
    // Closing asks about the unsaved changes; Discard closes cleanly and removes the recovery file.
    bool asked = false;
    answerNextQuestion(&next, QMessageBox::Discard, &asked);
    QVERIFY(next.close());
    QVERIFY(asked);
    QVERIFY(!next.autosave()->hasRecovery());
  }

  // Two studios at once each hold their own recovery slot: neither writes nor discards the
  // other's file; a studio started after one crashed takes over the crashed one's slot and
  // finds its recovery, not a free slot's (before: one recovery.mlod for every studio).
  void twoStudiosKeepTheirOwnRecovery() {
    Document first, second, third;
    auto a = std::make_unique<Autosave>(&first);
    auto b = std::make_unique<Autosave>(&second);
    QVERIFY(a->path() != b->path());
    QVERIFY(!a->hasRecovery() && !b->hasRecovery());
    const QString crashed = b->path();
    QFile written(crashed);
    QVERIFY(written.open(QIODevice::WriteOnly));
    written.write("the second studio's work");
    written.close();
    QVERIFY(b->hasRecovery());
    QVERIFY(!a->hasRecovery());
    a->discard(); // the first studio closes cleanly: the second's file stays
    a.reset();
    QVERIFY(QFile::exists(crashed));
    b.reset(); // the second crashes: no discard(), its slot is free again
    // the first slot is free and empty, the second free with a recovery: the second
    Autosave c(&third);
    QCOMPARE(c.path(), crashed);
    QVERIFY(c.hasRecovery());
    c.discard();
    QVERIFY(!QFile::exists(crashed));
    // and with nothing to recover, the first slot
    Autosave d(&first);
    QVERIFY(d.path() != crashed);
    QVERIFY(!d.hasRecovery());
  }

  // A saved project edited and lost in a crash comes back as that project: its file name,
  // unsaved, and Save writes there with the asset path the project file stored (issue 26:
  // it came back as "Untitled*" and Ctrl+S asked for a new name).
  void recoverKeepsTheProjectFile() {
    QTemporaryDir dir;
    const QString path = dir.filePath("recovered.mlod");
    std::string storedAsset;
    {
      auto window = openSample();
      QVERIFY(window);
      QVERIFY(window->saveProject(path));
      storedAsset = window->document()->project().assets[0].path;
      QVERIFY(editThreshold(*window, jointIndex(*window, "RightArm"), "250"));
      QVERIFY(waitForFigures(window->document()));
      QVERIFY(window->autosave()->saveNow());
      // No close(): the window goes away as in a crash and leaves the recovery file.
      window->hide();
    }
    MainWindow next;
    next.show();
    QSignalSpy opened(next.document(), &Document::projectOpened);
    QVERIFY(next.offerRecovery(false));
    QVERIFY(opened.wait(60000));
    QVERIFY(waitForFigures(next.document()));
    QCOMPARE(next.document()->fileName(), QFileInfo(path).absoluteFilePath());
    QVERIFY(next.document()->isModified());
    QVERIFY(next.windowTitle().contains("recovered"));
    QCOMPARE(next.document()->project().assets[0].path, storedAsset);
    QVERIFY(next.saveProject(next.document()->fileName()));
    QVERIFY(!next.document()->isModified());
    QVERIFY(!next.autosave()->hasRecovery());
    QVERIFY(!QFile::exists(Document::recoveryOriginPath(next.autosave()->path())));
    const Result<Project> reread = loadProjectFile(path.toStdString());
    QVERIFY(reread);
    QCOMPARE(reread->assets[0].path, storedAsset);
    QCOMPARE(*reread->assets[0].joints.at("RightArm").thresholds[1], 250.0);
    QVERIFY(next.close()); // saved: nothing to ask
  }

  // Autosave through its own timers (not saveNow()): an edit starts the after-change timer,
  // which writes the recovery file; the periodic timer writes again only when there are
  // unsaved changes; a new window recovers the edit from what the timers wrote.
  void autosaveTimersWriteTheRecovery() {
    Project lost;
    QString recovery;
    {
      auto window = openSample();
      QVERIFY(window);
      Autosave* autosave = window->autosave();
      recovery = autosave->path();
      autosave->discard();
      autosave->setDelays(50, 60 * 60 * 1000);
      QSignalSpy saved(autosave, &Autosave::saved);
      QSignalSpy changes(window->document()->undoStack(), &QUndoStack::indexChanged);
      QVERIFY(editThreshold(*window, jointIndex(*window, "RightArm"), "240"));
      // The timer may fire while the edit is still being typed: count, do not wait for a
      // signal that has already come. Tolerance: the after-change timer restarts on every
      // change of the undo stack and writes once they pause for 50 ms, so the edit writes at
      // least once and at most once per change it made (a loaded machine may pause between
      // two of them), plus once for a timer the import armed that setDelays() restarted; the
      // periodic timer, an hour away, writes nothing here.
      QTRY_VERIFY_WITH_TIMEOUT(saved.count() >= 1, 10000);
      QVERIFY(changes.count() >= 1);
      QVERIFY2(saved.count() <= changes.count() + 1,
               qPrintable(QString("%1 saves for %2 changes").arg(saved.count()).arg(changes.count())));
      QVERIFY(autosave->hasRecovery());
      QVERIFY(waitForFigures(window->document()));
      // The periodic timer: writes while the document is modified, so a second edit that
      // the after-change timer never sees (set far away) is still saved within a period.
      autosave->setDelays(60 * 60 * 1000, 100);
      QVERIFY(editThreshold(*window, jointIndex(*window, "RightArm"), "260"));
      QCOMPARE(*window->document()->project().assets[0].joints.at("RightArm").thresholds[1], 260.0);
      QTRY_VERIFY_WITH_TIMEOUT(saved.count() >= 2, 10000);
      QVERIFY(waitForFigures(window->document()));
      const int before = static_cast<int>(saved.count());
      QTRY_VERIFY_WITH_TIMEOUT(saved.count() > before, 10000); // again a period later: still unsaved
      lost = window->document()->project();
      window->hide(); // a crash: no close(), the recovery file stays
    }
    MainWindow next;
    next.show();
    QCOMPARE(next.autosave()->path(), recovery);
    QVERIFY(next.autosave()->hasRecovery());
    QSignalSpy opened(next.document(), &Document::projectOpened);
    QVERIFY(next.offerRecovery(false));
    QVERIFY(opened.wait(60000));
    QVERIFY(waitForFigures(next.document()));
    QCOMPARE(*next.document()->project().assets[0].joints.at("RightArm").thresholds[1], 260.0);
    QVERIFY(next.document()->lods() == lodSetFor(lost, lost.view.asset));
    next.autosave()->discard();
    QVERIFY(!next.autosave()->hasRecovery());
  }

  // A long job (a worker held by the test hook) shows progress; Cancel leaves the document as it was.
  void cancelLongJob() {
    auto window = openSample();
    QVERIFY(window);
    Document* document = window->document();
    const Figures before = figuresOf(*document);
    const Project project = document->project();
    const int steps = document->undoStack()->count();
    document->analysisRunner()->setWorkerHook([](const std::atomic<bool>& cancel) {
      while (!cancel.load())
        QThread::msleep(5);
    });
    QTest::mouseClick(window->findChild<QToolButton*>("addLevelButton"), Qt::LeftButton);
    QVERIFY(document->isAnalysing());
    QTRY_VERIFY_WITH_TIMEOUT(window->analysisProgress() && window->analysisProgress()->isVisible(), 20000);
    auto* cancel = window->analysisProgress()->findChild<QPushButton*>();
    QVERIFY(cancel);
    QTest::mouseClick(cancel, Qt::LeftButton);
    QTRY_VERIFY_WITH_TIMEOUT(!document->isAnalysing(), 20000);
    document->analysisRunner()->setWorkerHook({});
    QVERIFY(document->project() == project);
    QCOMPARE(document->undoStack()->count(), steps);
    QVERIFY(!document->undoStack()->canRedo()); // the cancelled edit is gone, not waiting to be redone
    QVERIFY(figuresOf(*document) == before);
    QVERIFY(window->logText().contains("cancelled"));
  }

  // Generating the levels from a pixel budget runs off the UI thread behind a progress
  // dialog: Cancel (the worker held by the test hook until then) leaves the document as it
  // was; a run that lands replaces the LOD set in one undo step.
  void generateLevelsCancelThenLand() {
    auto window = openSample();
    QVERIFY(window);
    Document* document = window->document();
    const Project project = document->project();
    const int steps = document->undoStack()->count();
    document->levelGenerator()->setWorkerHook([](const std::atomic<bool>& cancel) {
      while (!cancel.load())
        QThread::msleep(5);
    });
    QVERIFY(window->generateLevels(1.0, 4));
    QVERIFY(document->levelGenerator()->isRunning());
    QTRY_VERIFY_WITH_TIMEOUT(window->levelsProgress() && window->levelsProgress()->isVisible(), 20000);
    auto* cancel = window->levelsProgress()->findChild<QPushButton*>();
    QVERIFY(cancel);
    QTest::mouseClick(cancel, Qt::LeftButton);
    QVERIFY(!document->levelGenerator()->isRunning());
    QVERIFY(!window->levelsProgress()->isVisible());
    document->levelGenerator()->setWorkerHook({});
    QVERIFY(document->project() == project);
    QCOMPARE(document->undoStack()->count(), steps);
    QVERIFY(window->logText().contains("Level generation cancelled"));

    QSignalSpy finished(document->levelGenerator(), &LevelGenerator::finished);
    QTRY_VERIFY_WITH_TIMEOUT(!document->levelGenerator()->isBusy(), 20000); // the held worker returns after the cancel
    QVERIFY(window->generateLevels(1.0, 4));
    QVERIFY(finished.wait(120000));
    QVERIFY2(finished.first()[0].toBool(), qPrintable(finished.first()[1].toString()));
    QCOMPARE(document->undoStack()->count(), steps + 1);
    const LodSet& lods = document->lods();
    QCOMPARE(lods.levels.size(), std::size_t(4));
    QVERIFY(!lods.validate());
    QCOMPARE(lods.levels[0].motionThreshold, 0.0);
    QVERIFY(lods.levels[3].switchDistanceCm > 0.0);
    QVERIFY(lods.boundingRadiusCm > 0.0);
    QCOMPARE(window->levelsView()->model()->rowCount(), 4);
    QVERIFY(waitForFigures(document));
    QCOMPARE(document->analysis()->levelCount(), 4);
    document->undoStack()->undo();
    QVERIFY(document->lods() == lodSetFor(project, document->currentAsset()));
  }

  // On a character (a skinned mesh) with a motion assigned, the generated levels reduce the
  // mesh too, and hold for the assigned motion (retargeted) as well as the character's own clip.
  void generateLevelsForACharacter() {
    auto window = openSample();
    QVERIFY(window);
    Document* document = window->document();
    QSignalSpy imported(window.get(), &MainWindow::importFinished);
    window->importFileWithUnit(QString(MLOD_ASSIMP_MODELS) + "/X/BCN_Epileptic.X", 0.0);
    QVERIFY(imported.wait(60000));
    document->setCurrentAsset(0);
    QVERIFY(waitForFigures(document));
    QVERIFY(edit::assignMotion(*document, 0, 1));
    document->setCurrentAsset(1);
    QVERIFY(waitForFigures(document));
    QSignalSpy finished(document->levelGenerator(), &LevelGenerator::finished);
    // The Budget dialog: 3 levels, its preview computed in the background, then Apply.
    QTest::mouseClick(window->findChild<QToolButton*>("generateLevelsButton"), Qt::LeftButton);
    auto* dialog = window->findChild<BudgetDialog*>("budgetDialog");
    QVERIFY(dialog);
    dialog->findChild<QSpinBox*>("levelsBox")->setValue(3);
    QTRY_VERIFY_WITH_TIMEOUT(dialog->isPreviewCurrent(), 240000);
    QCOMPARE(dialog->table()->rowCount(), 3);
    QTest::mouseClick(dialog->applyButton(), Qt::LeftButton);
    QCOMPARE(finished.count(), 1);
    QVERIFY2(finished.first()[0].toBool(), qPrintable(finished.first()[1].toString()));
    const LodSet& lods = document->lods();
    QCOMPARE(lods.levels.size(), std::size_t(3));
    QVERIFY(!lods.validate());
    QVERIFY(lods.levels[0].triangles > 0);
    QVERIFY(lods.levels[2].meshRatio < 1.0);
    QVERIFY(lods.levels[2].switchDistanceCm >= lods.levels[1].switchDistanceCm);
  }

  // The Table 1 view shows exactly what `motionlod simplify` prints for the same settings.
  void table1MatchesCommandLine() {
    auto window = openSample();
    QVERIFY(window);
    QProcess cli;
    cli.start(MLOD_CLI, {"simplify", MLOD_SAMPLE, "--unit-scale", "cmu", "--threshold", "5,50,100,300", "--json"});
    QVERIFY(cli.waitForFinished(120000));
    QCOMPARE(cli.exitCode(), 0);
    const QJsonObject report = QJsonDocument::fromJson(cli.readAllStandardOutput()).object();
    const QJsonArray levels = report["thresholds"].toArray();
    QCOMPARE(levels.size(), 4);
    const QTableWidget* table = window->statisticsView()->table();
    const auto analysis = window->document()->analysis();
    for (int l = 0; l < 4; ++l) {
      const QJsonObject level = levels[l].toObject();
      const JpcLevelResult& mine = analysis->levels[std::size_t(l) + 1]; // level 0 is the original
      QCOMPARE(mine.simplifiedPercent, level["simplified_joint_percent"].toDouble());
      QCOMPARE(mine.clusterCount, level["clusters"].toInt());
      QCOMPARE(mine.maxError, level["max_error"].toDouble());
      QCOMPARE(mine.maxJointPositionErrorCm, level["max_joint_position_error_cm"].toDouble());
      QCOMPARE(table->item(StatisticsView::SimplifiedRow, l + 1)->text(),
               QString::number(level["simplified_joint_percent"].toDouble(), 'f', 1)); // column = level
      QCOMPARE(table->item(StatisticsView::ClustersRow, l + 1)->text(), QString::number(level["clusters"].toInt()));
      QCOMPARE(table->item(StatisticsView::MaxPositionRow, l + 1)->text(),
               QString::number(level["max_joint_position_error_cm"].toDouble(), 'f', 3));
    }
  }

  // `motionlod simplify PROJECT.mlod` prints exactly the figures the editor shows for that
  // project: per-joint thresholds (through the delegate), locks, alpha, a renamed and
  // re-thresholded level.
  void savedProjectMatchesCommandLine() {
    QTemporaryDir dir;
    const QString path = dir.filePath("tuned.mlod");
    auto window = openSample();
    QVERIFY(window);
    Document* document = window->document();
    QVERIFY(editThreshold(*window, jointIndex(*window, "LeftUpLeg"), "2"));
    edit::setJointsLocked(*document, {jointIndex(*window, "Spine1")}, true);
    edit::setAlpha(*document, 6.5);
    QVERIFY(editLevelCell(*window, 3, LevelsModel::ThresholdColumn, "120"));
    QVERIFY(waitForFigures(document));
    QVERIFY(window->saveProject(path));
    QProcess cli;
    cli.start(MLOD_CLI, {"simplify", path, "--json"});
    QVERIFY(cli.waitForFinished(120000));
    QCOMPARE(cli.exitCode(), 0);
    const QJsonObject report = QJsonDocument::fromJson(cli.readAllStandardOutput()).object();
    QCOMPARE(report["alpha"].toDouble(), 6.5);
    const QJsonArray levels = report["thresholds"].toArray();
    const auto analysis = document->analysis();
    QCOMPARE(levels.size(), analysis->levelCount() - 1); // the original is no clustering
    const QTableWidget* table = window->statisticsView()->table();
    for (int l = 1; l < analysis->levelCount(); ++l) {
      const QJsonObject level = levels[l - 1].toObject();
      const JpcLevelResult& mine = analysis->levels[std::size_t(l)];
      QCOMPARE(mine.threshold, level["threshold"].toDouble());
      QCOMPARE(mine.simplifiedPercent, level["simplified_joint_percent"].toDouble());
      QCOMPARE(mine.clusterCount, level["clusters"].toInt());
      QCOMPARE(mine.maxError, level["max_error"].toDouble());
      QCOMPARE(mine.maxJointPositionErrorCm, level["max_joint_position_error_cm"].toDouble());
      QCOMPARE(table->item(StatisticsView::SimplifiedRow, l)->text(),
               QString::number(level["simplified_joint_percent"].toDouble(), 'f', 1));
      for (const QJsonValue& value : level["joints"].toArray()) {
        const QJsonObject joint = value.toObject();
        const int j = jointIndex(*window, joint["name"].toString().toUtf8().constData());
        QCOMPARE(mine.joints[std::size_t(j)].clusters, joint["clusters"].toInt());
        QCOMPARE(mine.joints[std::size_t(j)].simplifiedPercent, joint["simplified_percent"].toDouble());
      }
    }
    const int leftUpLeg = jointIndex(*window, "LeftUpLeg");
    QCOMPARE(analysis->levels[1].joints[std::size_t(leftUpLeg)].threshold, 2.0);
    QVERIFY(analysis->levels[1].joints[std::size_t(jointIndex(*window, "Spine1"))].locked);
  }

  // A project whose asset moved opens with the asset marked missing; relinking brings it back.
  void relinkMissingAsset() {
    QTemporaryDir dir;
    const QString copy = dir.filePath("clip.bvh");
    QVERIFY(QFile::copy(MLOD_SAMPLE, copy));
    const QString path = dir.filePath("p.mlod");
    {
      MainWindow window;
      QSignalSpy spy(&window, &MainWindow::importFinished);
      window.importFileWithUnit(copy, 2.54 / 0.45);
      QVERIFY(spy.wait(60000));
      QVERIFY(waitForFigures(window.document()));
      QVERIFY(window.saveProject(path));
      QCOMPARE(window.document()->project().assets[0].path, std::string("clip.bvh")); // relative
    }
    const QString moved = dir.filePath("moved.bvh");
    QVERIFY(QFile::rename(copy, moved));
    MainWindow window;
    window.show();
    QSignalSpy opened(window.document(), &Document::projectOpened);
    QVERIFY(window.openProject(path));
    QVERIFY(opened.wait(60000));
    QCOMPARE(opened.first()[0].toBool(), false);
    QVERIFY(window.assetModel()->isMissing(0));
    QVERIFY(window.logText().contains("relink"));
    QVERIFY(!window.document()->analysis());
    QSignalSpy relinked(window.document(), &Document::projectOpened);
    window.document()->relinkAsset(0, moved);
    QVERIFY(relinked.wait(60000));
    QVERIFY(waitForFigures(window.document()));
    QVERIFY(!window.assetModel()->isMissing(0));
    QCOMPARE(window.document()->project().assets[0].path, std::string("moved.bvh"));
  }

  // The dock layout comes back in the next session (QSettings).
  void layoutIsRestored() {
    {
      MainWindow window;
      window.show();
      QVERIFY(QTest::qWaitForWindowExposed(&window));
      auto* statistics = window.findChild<QDockWidget*>("statisticsDock");
      QVERIFY(statistics && statistics->isVisible());
      statistics->toggleViewAction()->trigger();
      QVERIFY(!statistics->isVisible());
      window.close();
    }
    {
      MainWindow window;
      window.show();
      QVERIFY(QTest::qWaitForWindowExposed(&window));
      auto* statistics = window.findChild<QDockWidget*>("statisticsDock");
      QVERIFY(!statistics->isVisible());
      statistics->toggleViewAction()->trigger();
      window.close();
    }
    MainWindow again;
    again.show();
    QVERIFY(again.findChild<QDockWidget*>("statisticsDock")->isVisible());
    QCOMPARE(again.centralWidget(), again.findChild<ViewportPanel*>("viewportPanel"));
  }

  // Changing an asset's unit imports it again: one undo step, and undo gives the exact figures back.
  void assetUnitScaleIsOneUndoStep() {
    auto window = openSample();
    QVERIFY(window);
    Document* document = window->document();
    const Figures before = figuresOf(*document);
    const int steps = document->undoStack()->count();
    QSignalSpy changed(document, &Document::unitScaleChanged);
    document->setAssetUnitScale(0, 1.0);
    QVERIFY(changed.wait(60000));
    QCOMPARE(changed.first()[0].toBool(), true);
    QVERIFY(waitForFigures(document));
    QCOMPARE(document->asset(0)->unitScale, 1.0);
    QCOMPARE(document->project().assets[0].unitScale, 1.0);
    QCOMPARE(document->undoStack()->count(), steps + 1);
    QVERIFY(figuresOf(*document) != before); // E_pos and cm errors scale with the unit
    document->undoStack()->undo();
    QVERIFY(waitForFigures(document));
    QVERIFY(figuresOf(*document) == before);
  }

  // Switch distances generated at one unit are stale at another: the studio offers to
  // generate them again from the budget they were made for (switchDistancePixelBudget()),
  // and Regenerate does.
  void aNewUnitOffersToRegenerateStaleDistances() {
    auto window = openSample();
    QVERIFY(window);
    Document* document = window->document();
    QSignalSpy finished(document->levelGenerator(), &LevelGenerator::finished);
    QVERIFY(window->generateLevels(2.0, 3));
    QVERIFY(finished.wait(120000));
    QVERIFY2(finished.first()[0].toBool(), qPrintable(finished.first()[1].toString()));
    QVERIFY(waitForFigures(document));
    const double distance = document->lods().levels[2].switchDistanceCm;
    QVERIFY(distance > 0.0);
    QSignalSpy changed(document, &Document::unitScaleChanged);
    document->setAssetUnitScale(0, 1.0); // the sample is in CMU units (5.6444 cm): 5.6 x smaller
    QVERIFY(changed.wait(60000));
    QVERIFY(changed.first()[0].toBool());
    auto* box = window->findChild<QMessageBox*>("staleDistancesBox");
    QVERIFY(box);
    QVERIFY2(box->informativeText().contains("2 px, 3 levels"), qPrintable(box->informativeText()));
    QVERIFY(window->logText().contains("stale"));
    finished.clear();
    QTest::mouseClick(box->findChild<QPushButton*>("regenerateButton"), Qt::LeftButton);
    QVERIFY(finished.wait(120000));
    QVERIFY2(finished.first()[0].toBool(), qPrintable(finished.first()[1].toString()));
    const double regenerated = document->lods().levels[2].switchDistanceCm;
    QVERIFY2(regenerated > 0.0 && regenerated < 0.5 * distance,
             qPrintable(QStringLiteral("%1 cm at 5.6444 cm per unit, %2 cm at 1").arg(distance).arg(regenerated)));
    QVERIFY(waitForFigures(document));
  }

  // Removing an asset is undoable; the Assets dock counts what is there.
  void removeAssetAndUndo() {
    auto window = openSample();
    QVERIFY(window);
    Document* document = window->document();
    const Figures before = figuresOf(*document);
    auto* dock = window->findChild<QDockWidget*>("assetsDock");
    QCOMPARE(dock->windowTitle(), QString("Assets — 0 characters, 1 motion"));
    window->findChild<QAction*>("actionRemoveAsset")->trigger();
    QCOMPARE(document->assetCount(), 0);
    QCOMPARE(window->assetModel()->assetCount(), 0);
    QVERIFY(!document->analysis());
    QCOMPARE(dock->windowTitle(), QString("Assets — 0 characters, 0 motions"));
    press(*window, Qt::Key_Z, Qt::ControlModifier);
    QVERIFY(waitForFigures(document));
    QCOMPARE(document->assetCount(), 1);
    QVERIFY(figuresOf(*document) == before);
  }

  // The clustering mode is one undoable edit; optimal covers at least as many frames as greedy.
  void modeIsAnUndoableEdit() {
    auto window = openSample();
    QVERIFY(window);
    Document* document = window->document();
    const Figures greedy = figuresOf(*document);
    const std::vector<JpcLevelResult> greedyLevels = document->analysis()->levels;
    QComboBox* mode = window->modeBox();
    mode->setFocus();
    QTest::keyClick(mode, Qt::Key_Down);
    QCOMPARE(document->project().mode, JpcMode::Optimal);
    QVERIFY(waitForFigures(document));
    for (std::size_t l = 0; l < greedyLevels.size(); ++l)
      QVERIFY(document->analysis()->levels[l].simplifiedPercent >= greedyLevels[l].simplifiedPercent);
    press(*window, Qt::Key_Z, Qt::ControlModifier);
    QVERIFY(waitForFigures(document));
    QCOMPARE(mode->currentIndex(), 0);
    QVERIFY(figuresOf(*document) == greedy);
  }

  // Opening a project over unsaved changes asks first; No keeps everything.
  void openOverUnsavedChangesAsks() {
    QTemporaryDir dir;
    const QString path = dir.filePath("other.mlod");
    QFile file(path);
    QVERIFY(file.open(QIODevice::WriteOnly));
    file.write(QByteArray::fromStdString(projectToJson(Project{})));
    file.close();
    auto window = openSample();
    QVERIFY(window);
    QVERIFY(window->document()->isModified());
    bool asked = false;
    answerNextQuestion(window.get(), QMessageBox::No, &asked);
    QVERIFY(!window->openProject(path));
    QVERIFY(asked);
    QCOMPARE(window->document()->assetCount(), 1);
    QCOMPARE(window->document()->undoStack()->count(), 1);
  }

  // File > New Project (Ctrl+N): over unsaved changes it asks first and "No" keeps them;
  // "Yes" leaves an empty, untitled project with no undo history.
  void newProjectAsksThenStartsEmpty() {
    auto window = openSample();
    QVERIFY(window);
    Document* document = window->document();
    QVERIFY(document->isModified());
    QAction* action = window->findChild<QAction*>("actionNewProject");
    QVERIFY(action);
    QCOMPARE(action->shortcut(), QKeySequence(QKeySequence::New));
    bool asked = false;
    answerNextQuestion(window.get(), QMessageBox::No, &asked);
    action->trigger();
    QVERIFY(asked);
    QCOMPARE(document->assetCount(), 1);
    QVERIFY(document->isModified());
    asked = false;
    answerNextQuestion(window.get(), QMessageBox::Yes, &asked);
    action->trigger();
    QVERIFY(asked);
    QCOMPARE(document->assetCount(), 0);
    QCOMPARE(document->undoStack()->count(), 0);
    QVERIFY(!document->isModified());
    QVERIFY(document->fileName().isEmpty());
    QVERIFY(!document->analysis());
    QVERIFY(window->logText().contains("New project"));
  }

  // A motion assigned to a character (automatic joint mapping) is one undo step, shows in the
  // Assets dock, survives save and reopen, and goes with the character when it is removed.
  void assignMotionToCharacter() {
    auto window = openSample();
    QVERIFY(window);
    Document* document = window->document();
    QSignalSpy spy(window.get(), &MainWindow::importFinished);
    window->importFileWithUnit(QString(MLOD_ASSIMP_MODELS) + "/X/BCN_Epileptic.X", 0.0);
    QVERIFY(spy.wait(60000));
    QCOMPARE(spy.first()[0].toBool(), true);
    QCOMPARE(document->assetCount(), 2);
    document->setCurrentAsset(0);
    QVERIFY(waitForFigures(document));
    const int steps = document->undoStack()->count();
    press(*window, Qt::Key_M, Qt::ControlModifier | Qt::ShiftModifier);
    QCOMPARE(document->undoStack()->count(), steps + 1);
    QCOMPARE(document->project().mappings.size(), std::size_t(1));
    const ProjectMapping mapping = document->project().mappings[0];
    QCOMPARE(mapping.motion, 0);
    QCOMPARE(mapping.character, 1);
    QVERIFY2(mapping.mapping.pairs.size() >= 15, qPrintable(QString::number(mapping.mapping.pairs.size())));
    QVERIFY(!mapping.mapping.validate(document->asset(0)->skeleton, document->asset(1)->skeleton));
    const QString detail = window->assetModel()->index(0, AssetTreeModel::DetailColumn).data().toString();
    QVERIFY2(detail.startsWith("drives BCN_Epileptic.X"), qPrintable(detail));
    QVERIFY(!window->findChild<QMessageBox*>("warningBox")); // 24 of its 33 joints with a child: it fits

    QTemporaryDir dir;
    QVERIFY(window->saveProject(dir.filePath("assigned.mlod")));
    {
      MainWindow reopened;
      QSignalSpy opened(reopened.document(), &Document::projectOpened);
      QVERIFY(reopened.openProject(dir.filePath("assigned.mlod")));
      QVERIFY(opened.wait(60000));
      QVERIFY(reopened.document()->project().mappings == document->project().mappings);
    }
    // Removing the character drops the mapping; undo brings both back.
    document->setCurrentAsset(1);
    window->findChild<QAction*>("actionRemoveAsset")->trigger();
    QCOMPARE(document->assetCount(), 1);
    QVERIFY(document->project().mappings.empty());
    document->undoStack()->undo();
    QCOMPARE(document->assetCount(), 2);
    QCOMPARE(document->project().mappings.size(), std::size_t(1));
    QVERIFY(document->project().mappings[0] == mapping);
    document->undoStack()->undo(); // the assignment
    QVERIFY(document->project().mappings.empty());
  }

  // A biped clip assigned to a quadruped (the sample onto Testwuson: 7 joint pairs) is
  // assigned, but the user is told it drives too little of the character, by the rule
  // `motionlod export --motion` refuses by (core's drivesTooLittle()): a warning box, the log
  // and the status bar (issue 26, item 7: it stood the quadruped upright without a word).
  void assigningAForeignRigWarns() {
    auto window = openSample();
    QVERIFY(window);
    Document* document = window->document();
    QSignalSpy spy(window.get(), &MainWindow::importFinished);
    window->importFileWithUnit(QString(MLOD_ASSIMP_MODELS) + "/X/Testwuson.X", 0.0);
    QVERIFY(spy.wait(60000));
    QCOMPARE(spy.first()[0].toBool(), true);
    document->setCurrentAsset(0);
    QVERIFY(waitForFigures(document));
    const int steps = document->undoStack()->count();
    press(*window, Qt::Key_M, Qt::ControlModifier | Qt::ShiftModifier);
    QCOMPARE(document->undoStack()->count(), steps + 1); // assigned all the same: the user may edit the table
    QCOMPARE(document->project().mappings.size(), std::size_t(1));
    const MappingCoverage coverage =
        mappingCoverage(document->project().mappings[0].mapping, document->asset(1)->skeleton);
    QVERIFY(drivesTooLittle(coverage));
    const QString reach = QString::fromStdString(mappingReach(coverage, "Testwuson.X"));
    auto* box = window->findChild<QMessageBox*>("warningBox");
    QVERIFY(box);
    QTRY_VERIFY(box->isVisible());
    QVERIFY2(box->informativeText().contains(reach) && box->informativeText().contains("below 50%"),
             qPrintable(box->informativeText()));
    QVERIFY2(window->logText().contains("warning: cmu_01_01_excerpt.bvh on Testwuson.X: the automatic mapping drives " +
                                        reach),
             qPrintable(window->logText()));
    QVERIFY2(window->statusBar()->currentMessage().contains(reach), qPrintable(window->statusBar()->currentMessage()));
    box->accept();
  }

  // The joint-mapping table: a combo box per character joint edits the pair through the
  // delegate (one undo step), "(none)" unmaps, Automatic restores the name match; the edited
  // table is saved in the .mlod.
  void editJointMappingTable() {
    auto window = openSample();
    QVERIFY(window);
    Document* document = window->document();
    QSignalSpy spy(window.get(), &MainWindow::importFinished);
    window->importFileWithUnit(QString(MLOD_ASSIMP_MODELS) + "/X/BCN_Epileptic.X", 0.0);
    QVERIFY(spy.wait(60000));
    document->setCurrentAsset(0);
    QVERIFY(waitForFigures(document));
    press(*window, Qt::Key_M, Qt::ControlModifier | Qt::ShiftModifier); // assign
    QCOMPARE(document->project().mappings.size(), std::size_t(1));
    const MotionMapping automatic = document->project().mappings[0].mapping;
    press(*window, Qt::Key_M, Qt::ControlModifier | Qt::AltModifier);
    auto* dialog = window->findChild<MappingDialog*>("mappingDialog");
    QVERIFY(dialog);
    QVERIFY(QTest::qWaitForWindowExposed(dialog));
    QTableView* table = dialog->table();
    const Skeleton& character = document->asset(1)->skeleton;
    QCOMPARE(table->model()->rowCount(), character.jointCount());
    // A mapped character joint, and a motion joint other than its own.
    int row = -1;
    for (int r = 0; r < character.jointCount() && row < 0; ++r)
      if (automatic.motionFor(character.joints[std::size_t(r)].name))
        row = r;
    QVERIFY(row >= 0);
    const std::string characterJoint = character.joints[std::size_t(row)].name;
    const std::string before = *automatic.motionFor(characterJoint);
    QCOMPARE(table->model()->index(row, MappingModel::MotionColumn).data().toString(), QString::fromStdString(before));
    const int steps = document->undoStack()->count();
    const auto chooseInCell = [&](int r, int offset) -> QString {
      const QModelIndex cell = table->model()->index(r, MappingModel::MotionColumn);
      table->scrollTo(cell);
      table->setFocus();
      table->selectionModel()->setCurrentIndex(cell, QItemSelectionModel::ClearAndSelect | QItemSelectionModel::Rows);
      QTest::keyClick(table, Qt::Key_F2);
      auto* box = qobject_cast<QComboBox*>(table->indexWidget(cell)); // the open editor (a closed one lingers until deleteLater)
      if (!box || box->objectName() != "motionJointEditor")
        return "no editor";
      const int target = offset == 0 ? 0 : (box->currentIndex() + offset) % box->count();
      while (box->currentIndex() != target)
        QTest::keyClick(box, box->currentIndex() < target ? Qt::Key_Down : Qt::Key_Up);
      const QString chosen = box->currentData().toString();
      QTest::keyClick(box, Qt::Key_Return);
      QCoreApplication::processEvents();
      return chosen;
    };
    const QString chosen = chooseInCell(row, 1);
    QVERIFY(chosen != "no editor" && !chosen.isEmpty() && chosen.toStdString() != before);
    QCOMPARE(document->undoStack()->count(), steps + 1);
    const MotionMapping& edited = document->project().mappings[0].mapping;
    QVERIFY(edited.motionFor(characterJoint) && *edited.motionFor(characterJoint) == chosen.toStdString());
    QCOMPARE(table->model()->index(row, MappingModel::MotionColumn).data().toString(), chosen);
    QVERIFY(!edited.validate(document->asset(0)->skeleton, character)); // set() kept it one-to-one
    // (none): the character joint keeps its rest pose.
    QCOMPARE(chooseInCell(row, 0), QString());
    QVERIFY(!document->project().mappings[0].mapping.motionFor(characterJoint));
    QCOMPARE(document->undoStack()->count(), steps + 2);
    // Ctrl+Z in the dialog undoes there; the table follows.
    QTest::keyClick(dialog, Qt::Key_Z, Qt::ControlModifier);
    QCOMPARE(table->model()->index(row, MappingModel::MotionColumn).data().toString(), chosen);
    const MotionMapping saved = document->project().mappings[0].mapping;
    QTemporaryDir dir;
    QVERIFY(window->saveProject(dir.filePath("mapped.mlod")));
    {
      MainWindow reopened;
      QSignalSpy opened(reopened.document(), &Document::projectOpened);
      QVERIFY(reopened.openProject(dir.filePath("mapped.mlod")));
      QVERIFY(opened.wait(60000));
      QVERIFY(reopened.document()->project().mappings[0].mapping == saved);
    }
    // Automatic: the name match again, one step.
    QTest::mouseClick(dialog->findChild<QPushButton*>("automaticMappingButton"), Qt::LeftButton);
    QVERIFY(document->project().mappings[0].mapping == automatic);
    document->undoStack()->undo();
    QVERIFY(document->project().mappings[0].mapping == saved);
  }

  // The common editor actions have shortcuts and tooltips.
  void editorActionsHaveShortcuts() {
    MainWindow window;
    const auto shortcut = [&](const char* name) { return window.findChild<QAction*>(name)->shortcut(); };
    QCOMPARE(shortcut("actionUndo"), QKeySequence(QKeySequence::Undo));
    QCOMPARE(shortcut("actionRedo"), QKeySequence(QKeySequence::Redo));
    QCOMPARE(shortcut("actionSave"), QKeySequence(QKeySequence::Save));
    QCOMPARE(shortcut("actionOpenProject"), QKeySequence("Ctrl+Shift+O"));
    QCOMPARE(shortcut("actionNewProject"), QKeySequence(QKeySequence::New));
    QCOMPARE(shortcut("actionLockJoints"), QKeySequence("Ctrl+L"));
    QCOMPARE(shortcut("actionNextLevel"), QKeySequence(Qt::Key_PageDown));
    QVERIFY(!window.findChild<QAction*>("actionApplyToChildren")->toolTip().isEmpty());
  }
};

QTEST_MAIN(TestEditor)
#include "test_editor.moc"
