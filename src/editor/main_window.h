#pragma once
// The studio's main window: builds the window, wires actions, restores the layout.
// Work happens in the Document (edits, figures, files), ImportJob and the views; this class
// only connects them.

#include "core/asset.h"
#include "io/import_options.h"

#include <QMainWindow>
#include <QPointer>

#include <memory>

namespace Ui { class MainWindow; }
class QActionGroup;
class QComboBox;
class QDockWidget;
class QDoubleSpinBox;
class QLabel;
class QMenu;
class QProgressDialog;
class QTableView;
class QTreeView;

namespace mlod {

class AssetTreeModel;
class Autosave;
class ClusteringTableView;
class CrowdPanel;
class ViewportPanel;
class Document;
class ImportJob;
class HelpBrowser;
class JobProgress;
class JointTreeModel;
class LevelsModel;
class BudgetDialog;
class MappingDialog;
class PluginHost;
class StatisticsView;
class TrajectoryView;

class MainWindow : public QMainWindow {
  Q_OBJECT
public:
  // `plugins`: the exporter plugins File > Export… offers (the caller keeps it alive and
  // loaded); null: the window loads the default ones itself on the first export.
  explicit MainWindow(QWidget* parent = nullptr, PluginHost* plugins = nullptr);
  ~MainWindow() override;

  Document* document() const { return m_document; }
  AssetTreeModel* assetModel() const { return m_assets; }
  PluginHost* pluginHost();
  ImportJob* importJob() const { return m_import; }
  Autosave* autosave() const { return m_autosave; }
  bool isImporting() const;
  // cm per file unit for the next imports; 0 = each file's own (ImportOptions::unitScale).
  void setImportUnitScale(double cmPerUnit);
  double importUnitScale() const { return m_unitScale; }
  QString logText() const;

  // The views, for tests and scripted checks.
  QTreeView* skeletonView() const { return m_skeletonView; }
  JointTreeModel* jointModel() const { return m_jointModel; }
  QTableView* levelsView() const { return m_levelsView; }
  ClusteringTableView* clusteringView() const { return m_clusteringView; }
  TrajectoryView* trajectoryView() const { return m_trajectoryView; }
  StatisticsView* statisticsView() const { return m_statisticsView; }
  QDoubleSpinBox* alphaBox() const { return m_alphaBox; }
  QComboBox* modeBox() const { return m_modeBox; }
  QProgressDialog* analysisProgress() const;
  QProgressDialog* importProgress() const;
  CrowdPanel* crowdPanel() const { return m_crowdPanel; }
  ViewportPanel* viewportPanel() const { return m_viewportPanel; }
  QDockWidget* crowdDock() const { return m_crowdDock; }
  // The character view (ViewportPanel) is the central widget; the Crowd dock sits beside it.
  // Brings a right-hand dock to the front at a height that shows its 3D view well.
  void showDock(QDockWidget* dock);
  QString statusText() const; // the permanent status-bar figures
  // Opens the joint-mapping table of the asset in view (its first mapping, as motion or
  // character); null, with a message, when it has none.
  MappingDialog* editMapping();
  // Generates the LOD set from a pixel budget in the background with a progress dialog
  // ("levelsProgress", Cancel drops the result); false with a message when it cannot start.
  bool generateLevels(double pixels, int levels);
  // Edit > Generate Levels from Pixel Budget…: the Budget dialog (window-modal, deleted on
  // close), seeded with the current levels' pixel error, count and projection.
  BudgetDialog* openBudgetDialog();
  QProgressDialog* levelsProgress() const;

  // A scripted run (motionlod-studio --screenshot) asks nothing: a question gets its safe
  // answer (assets outside a project's folder are not read; unsaved changes, of which a
  // scripted run has none, are not kept), as in a hidden window.
  void setUnattended(bool unattended) { m_unattended = unattended; }
  // Projects: errors show in a non-modal message box and the log; the document is kept.
  bool openProject(const QString& path);
  // File > New Project: an empty, untitled project; false when the user kept the unsaved changes.
  bool newProject();
  bool saveProject(const QString& path);
  // A recovery file left by a session that did not close cleanly: asks (unless `ask` is
  // false) and opens it as an unsaved project.
  bool offerRecovery(bool ask = true);

public slots:
  // Imports a file in the background with the import unit chosen in the menu (or, when
  // given, `unitScale` cm per file unit for this file alone); importFinished() follows.
  void importFile(const QString& path);
  void importFileWithUnit(const QString& path, double unitScale);
  void cancelImport();

signals:
  void importFinished(bool ok, const QString& path, const QString& message);

protected:
  void closeEvent(QCloseEvent* event) override;

private:
  bool mayAsk() const { return isVisible() && !m_unattended; }
  bool m_unattended = false;
  void onImported(const QString& path, std::shared_ptr<const Asset> asset);
  void onImportFailed(const QString& path, const QString& reason);
  void showAsset(const Asset& asset);
  void log(const QString& line);
  void chooseFile();
  void showAbout();
  void buildUnitMenu();
  void buildAssetUnitMenu(QMenu* edit);
  void refreshAssetUnitMenu();
  void offerToRegenerateDistances();
  void buildDocks(); // the docks below, in their first-run places, and their links to the document
  void buildSkeletonDock();
  void buildLevelsDock();
  void buildAnalysisDocks();
  void buildViewports();
  void buildStatusLabels();
  void connectDocument();
  void buildSummaryDock();
  void buildResetLayout(); // after every dock is in its first-run place
  void buildActions();
  void refreshViews();
  void selectDefaultJoint();
  void refreshStatus();
  void refreshTitle();
  void refreshRecentMenu();
  void addRecent(const QString& path);
  void showError(const QString& title, const QString& text, const QString& detail);
  // A warning the user sees (a non-modal box, objectName "warningBox"), also in the log and status bar.
  void showWarning(const QString& title, const QString& text, const QString& detail);
  std::vector<int> selectedJoints() const;
  QDockWidget* addDock(const QString& name, const QString& title, QWidget* widget, Qt::DockWidgetArea area);

  std::unique_ptr<Ui::MainWindow> m_ui;
  Document* m_document = nullptr;
  AssetTreeModel* m_assets = nullptr;
  PluginHost* m_plugins = nullptr;          // injected, or m_ownPlugins
  std::unique_ptr<PluginHost> m_ownPlugins; // loaded on the first export
  ImportJob* m_import = nullptr;
  Autosave* m_autosave = nullptr;
  JobProgress* m_progress = nullptr;
  JobProgress* m_analysisProgress = nullptr;
  QActionGroup* m_unitGroup = nullptr;
  double m_unitScale = 0.0;
  double m_pendingScale = 0.0;

  QTreeView* m_skeletonView = nullptr;
  JointTreeModel* m_jointModel = nullptr;
  QTableView* m_levelsView = nullptr;
  LevelsModel* m_levelsModel = nullptr;
  QPointer<MappingDialog> m_mappingDialog;
  JobProgress* m_levelsProgress = nullptr;
  ClusteringTableView* m_clusteringView = nullptr;
  TrajectoryView* m_trajectoryView = nullptr;
  StatisticsView* m_statisticsView = nullptr;
  QDoubleSpinBox* m_alphaBox = nullptr;
  QComboBox* m_modeBox = nullptr;
  CrowdPanel* m_crowdPanel = nullptr;
  ViewportPanel* m_viewportPanel = nullptr;
  QDockWidget* m_summaryDock = nullptr;
  QLabel* m_summaryLabel = nullptr;
  QDockWidget* m_crowdDock = nullptr;
  QDockWidget* m_skeletonDock = nullptr;
  QDockWidget* m_levelsDock = nullptr;
  QDockWidget* m_clusteringDock = nullptr;
  QDockWidget* m_trajectoryDock = nullptr;
  QDockWidget* m_statisticsDock = nullptr;
  // the actions that buttons also trigger (buildActions())
  QAction* m_addLevelAction = nullptr;
  QAction* m_generateLevelsAction = nullptr;
  QAction* m_saveAction = nullptr;
  QPointer<HelpBrowser> m_help; // the user guide, while open
  QMenu* m_recentMenu = nullptr;
  QMenu* m_assetUnitMenu = nullptr;
  int m_loggedIndex = 0; // the undo stack's index the log has told of
  QLabel* m_clipLabel = nullptr;
  QLabel* m_frameLabel = nullptr;
  QLabel* m_levelLabel = nullptr;
  QLabel* m_jointLabel = nullptr;
};

} // namespace mlod
