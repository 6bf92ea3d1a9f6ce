#pragma once
// The studio's main window: builds the window, wires actions, restores the layout.
// Work happens in ImportJob and the models; this class only connects them.

#include "core/asset.h"
#include "io/import_options.h"

#include <QMainWindow>

#include <memory>

namespace Ui { class MainWindow; }
class QActionGroup;
class QProgressDialog;

namespace mlod {

class AssetTreeModel;
class ImportJob;

class MainWindow : public QMainWindow {
  Q_OBJECT
public:
  explicit MainWindow(QWidget* parent = nullptr);
  ~MainWindow() override;

  AssetTreeModel* assetModel() const { return m_assets; }
  ImportJob* importJob() const { return m_import; }
  bool isImporting() const;
  // cm per file unit for the next imports; 0 = each file's own (ImportOptions::unitScale).
  void setImportUnitScale(double cmPerUnit);
  double importUnitScale() const { return m_unitScale; }
  QString logText() const;

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
  void onImported(const QString& path, std::shared_ptr<const Asset> asset);
  void onImportFailed(const QString& path, const QString& reason);
  void showAsset(const Asset& asset);
  void log(const QString& line);
  void chooseFile();
  void showAbout();
  void buildUnitMenu();

  std::unique_ptr<Ui::MainWindow> m_ui;
  AssetTreeModel* m_assets = nullptr;
  ImportJob* m_import = nullptr;
  QProgressDialog* m_progress = nullptr;
  QActionGroup* m_unitGroup = nullptr;
  double m_unitScale = 0.0;
};

} // namespace mlod
