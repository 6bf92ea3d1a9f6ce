#pragma once
// File > Export… (Ctrl+E; docs/architecture.md sections 7 and 8): the project's character through an
// exporter plugin. The plugin combo lists what the host loaded; the options form is built
// from the plugin's options as data (tooltips from their help); the output path's file
// picker filters by the plugin's suffixes; the levels to include are ticked. The LodPackage
// is built and exported off the UI thread (QtConcurrent) behind a progress dialog whose
// Cancel stops both (nothing is written); the result (message and the output's folder)
// shows in the dialog. The work itself is core's (buildLodPackage) and the plugin's.

#include <QDialog>
#include <QFutureWatcher>
#include <QPointer>
#include <QThreadPool>
#include <QVariantMap>

#include <atomic>
#include <functional>
#include <memory>

class QComboBox;
class QFormLayout;
class QLabel;
class QLineEdit;
class QListWidget;
class QProgressDialog;
class QPushButton;

namespace mlod {

class Document;
class PluginHost;
struct ExportResult;

// The first of `candidates` that is a folder this user can write to (the current folder
// when none is).
QString firstWritableFolder(const QStringList& candidates);

class ExportDialog : public QDialog {
  Q_OBJECT
public:
  ExportDialog(Document* document, const PluginHost* host, QWidget* parent = nullptr);
  ~ExportDialog() override;

  QComboBox* pluginCombo() const { return m_plugin; }
  QLineEdit* outputEdit() const { return m_output; }
  QListWidget* levelsList() const { return m_levels; }
  QWidget* optionWidget(const QString& key) const; // the editor of one option of the plugin in view
  QLabel* resultLabel() const { return m_result; }
  QProgressDialog* progressDialog() const { return m_progress; }
  bool isRunning() const { return m_running; }
  // The project's asset the package is made of: the character in view (or the character the
  // motion in view is assigned to); -1 when there is none.
  int exportedAsset() const { return m_asset; }
  // The option values the form holds, checked against the plugin's options; false and a
  // reason when one is out of range.
  bool currentOptions(QVariantMap* out_values, QString* out_error) const;

  // Test hook: runs on the worker before any work, with the cancel flag.
  void setWorkerHook(std::function<void(const std::atomic<bool>&)> hook) { m_hook = std::move(hook); }

public slots:
  // Starts the export with what the dialog holds (refused, with the reason in the result
  // label, while one runs, without an output path or a level, or with a bad option).
  void startExport();

signals:
  void exportFinished(bool ok, const QString& message);

private:
  void rebuildOptions();
  void browse();
  void onFinished();
  void showResult(bool ok, const QString& message);

  Document* m_document;
  const PluginHost* m_host;
  int m_asset = -1;
  QComboBox* m_plugin;
  QFormLayout* m_options;
  QWidget* m_optionsBox;
  QLineEdit* m_output;
  QListWidget* m_levels;
  QLabel* m_assetLabel;
  QLabel* m_result;
  QPushButton* m_exportButton;
  QProgressDialog* m_progress = nullptr;
  bool m_running = false;
  QPointer<Document> m_exporting; // told of the export while it runs (a job the artist waits for)
  QString m_runningPath;
  std::shared_ptr<std::atomic<bool>> m_cancel;
  // The export's own thread: a long export never holds a thread of the global pool that the
  // document's analysis (and whatever waits for it) needs.
  QThreadPool m_pool;
  QFutureWatcher<std::shared_ptr<ExportResult>> m_watcher;
  std::function<void(const std::atomic<bool>&)> m_hook;
};

} // namespace mlod
