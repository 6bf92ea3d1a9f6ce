#include "editor/views/export_dialog.h"

#include "core/project_package.h"
#include "editor/document/document.h"
#include "sdk/plugin_host.h"

#include <QCheckBox>
#include <QComboBox>
#include <QDialogButtonBox>
#include <QDir>
#include <QDoubleSpinBox>
#include <QFileDialog>
#include <QFileInfo>
#include <QFormLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QListWidget>
#include <QPointer>
#include <QProgressDialog>
#include <QPushButton>
#include <QSettings>
#include <QStandardPaths>
#include <QSpinBox>
#include <QToolButton>
#include <QUrl>
#include <QVBoxLayout>
#include <QtConcurrent>

#include <limits>

namespace mlod {

ExportDialog::ExportDialog(Document* document, const PluginHost* host, QWidget* parent)
    : QDialog(parent), m_document(document), m_host(host) {
  setWindowTitle(tr("Export LOD Set"));
  setMinimumWidth(520);
  m_pool.setMaxThreadCount(1);
  setObjectName("exportDialog");
  auto* layout = new QVBoxLayout(this);

  const Project& project = document->project();
  // the character of the asset in view: the one the motion is viewed on (core's rule, as `motionlod export`)
  m_asset =
      exportCharacterOf(project, document->currentAsset(), document->viewedCharacter(), document->importedAssets());
  if (m_asset >= static_cast<int>(project.assets.size()))
    m_asset = -1;
  m_assetLabel = new QLabel(this);
  m_assetLabel->setObjectName("assetLabel");
  m_assetLabel->setText(m_asset >= 0 ? tr("Character: <b>%1</b>").arg(QFileInfo(document->assetFilePath(m_asset)).fileName())
                                     : tr("Nothing to export: import a character or a motion first (Ctrl+O)."));
  layout->addWidget(m_assetLabel);

  auto* form = new QFormLayout;
  m_plugin = new QComboBox(this);
  m_plugin->setObjectName("pluginCombo");
  m_plugin->setToolTip(tr("The exporter plugin that writes the file (found in MOTIONLOD_PLUGIN_PATH and the "
                          "installation's plugin folder)"));
  for (const PluginInfo& info : host->plugins())
    m_plugin->addItem(QStringLiteral("%1 (%2)").arg(info.name, info.suffixes.join(QStringLiteral(", ."))
                                                                  .prepend('.')),
                      info.id);
  form->addRow(tr("&Format:"), m_plugin);

  auto* outputRow = new QHBoxLayout;
  m_output = new QLineEdit(this);
  m_output->setObjectName("outputEdit");
  m_output->setToolTip(tr("The file to write; it is written through a temporary file, so a failed or cancelled "
                          "export leaves nothing"));
  auto* browseButton = new QToolButton(this);
  browseButton->setObjectName("browseButton");
  browseButton->setText(tr("…"));
  browseButton->setToolTip(tr("Choose the output file"));
  outputRow->addWidget(m_output);
  outputRow->addWidget(browseButton);
  auto* outputLabel = new QLabel(tr("&Output:"), this);
  outputLabel->setBuddy(m_output);
  form->addRow(outputLabel, outputRow);
  layout->addLayout(form);

  auto* optionsGroup = new QGroupBox(tr("Options"), this);
  m_optionsBox = optionsGroup;
  m_options = new QFormLayout(optionsGroup);
  layout->addWidget(optionsGroup);

  auto* levelsGroup = new QGroupBox(tr("Levels"), this);
  auto* levelsLayout = new QVBoxLayout(levelsGroup);
  m_levels = new QListWidget(this);
  m_levels->setObjectName("levelsList");
  m_levels->setToolTip(tr("The LOD levels to include; level 0 is the original"));
  const LodSet& lods = lodSetFor(project, m_asset); // the character's own levels
  for (std::size_t i = 0; i < lods.levels.size(); ++i) {
    const LodLevel& level = lods.levels[i];
    auto* item = new QListWidgetItem(
        i == 0 ? tr("%1 — original").arg(QString::fromStdString(level.name))
               : tr("%1 — E %2, mesh %3%, %4")
                     .arg(QString::fromStdString(level.name))
                     .arg(level.motionThreshold)
                     .arg(100.0 * level.meshRatio, 0, 'f', 0)
                     .arg(level.switchDistanceCm > 0.0 ? tr("from %1 m").arg(level.switchDistanceCm / 100.0, 0, 'f', 2)
                                                       : tr("switch distance not set")),
        m_levels);
    item->setFlags(item->flags() | Qt::ItemIsUserCheckable);
    item->setCheckState(Qt::Checked);
  }
  m_levels->setMaximumHeight(120);
  levelsLayout->addWidget(m_levels);
  layout->addWidget(levelsGroup);

  m_result = new QLabel(this);
  m_result->setObjectName("resultLabel");
  m_result->setWordWrap(true);
  m_result->setTextInteractionFlags(Qt::TextBrowserInteraction);
  m_result->setOpenExternalLinks(true);
  layout->addWidget(m_result);

  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Close, this);
  m_exportButton = buttons->addButton(tr("&Export"), QDialogButtonBox::AcceptRole);
  m_exportButton->setObjectName("exportButton");
  m_exportButton->setDefault(true);
  m_exportButton->setToolTip(tr("Build the LOD package and write it with the chosen plugin"));
  layout->addWidget(buttons);
  connect(buttons, &QDialogButtonBox::rejected, this, &QDialog::reject);
  connect(m_exportButton, &QPushButton::clicked, this, &ExportDialog::startExport);
  connect(browseButton, &QToolButton::clicked, this, &ExportDialog::browse);
  connect(m_plugin, &QComboBox::currentIndexChanged, this, [this] {
    m_result->clear(); // the last result was another format's
    rebuildOptions();
    // keep the output's name, change its suffix to the plugin's
    const PluginInfo* info = nullptr;
    for (const PluginInfo& candidate : m_host->plugins())
      if (candidate.id == m_plugin->currentData().toString())
        info = &candidate;
    if (info && !m_output->text().isEmpty()) {
      const QFileInfo file(m_output->text());
      if (!info->suffixes.contains(file.suffix(), Qt::CaseInsensitive))
        m_output->setText(file.dir().filePath(file.completeBaseName() + '.' + info->suffixes.value(0)));
    }
  });
  connect(&m_watcher, &QFutureWatcher<std::shared_ptr<ExportResult>>::finished, this, &ExportDialog::onFinished);

  const QString lastPlugin = QSettings().value("export/plugin").toString();
  const int lastIndex = m_plugin->findData(lastPlugin);
  m_plugin->setCurrentIndex(lastIndex >= 0 ? lastIndex : 0);
  rebuildOptions();
  if (m_asset >= 0 && m_plugin->count() > 0) {
    // A folder the export can be written to: the last one chosen, the project's, else
    // Documents; never the source's folder just because the asset is there (often read-only).
    const QString folder = firstWritableFolder(
        {QSettings().value("export/lastDir").toString(),
         document->fileName().isEmpty() ? QString() : QFileInfo(document->fileName()).absolutePath(),
         QStandardPaths::writableLocation(QStandardPaths::DocumentsLocation),
         QStandardPaths::writableLocation(QStandardPaths::HomeLocation), QDir::tempPath()});
    const QString suffix = m_host->plugins().value(m_plugin->currentIndex()).suffixes.value(0);
    m_output->setText(QDir(folder).filePath(QFileInfo(document->assetFilePath(m_asset)).completeBaseName() + '.' + suffix));
  }
  if (m_plugin->count() == 0) {
    QStringList reasons;
    for (const PluginFailure& failure : host->failures())
      reasons << QStringLiteral("%1: %2").arg(QFileInfo(failure.file).fileName(), failure.reason);
    showResult(false, tr("No exporter plugin was found.%1")
                          .arg(reasons.isEmpty() ? QString() : QStringLiteral("<br>") + reasons.join(QStringLiteral("<br>"))));
  }
  m_exportButton->setEnabled(m_asset >= 0 && m_plugin->count() > 0);
}

QString firstWritableFolder(const QStringList& candidates) {
  for (const QString& folder : candidates) {
    const QFileInfo info(folder);
    if (!folder.isEmpty() && info.isDir() && info.isWritable())
      return info.absoluteFilePath();
  }
  return QDir::currentPath();
}

ExportDialog::~ExportDialog() {
  if (m_cancel)
    m_cancel->store(true);
  m_watcher.waitForFinished(); // the worker holds references to this dialog's data: let it stop
  if (m_running && m_exporting)
    m_exporting->endWaitedJob();
}

QWidget* ExportDialog::optionWidget(const QString& key) const {
  return m_optionsBox->findChild<QWidget*>(QStringLiteral("option_") + key);
}

void ExportDialog::rebuildOptions() {
  while (m_options->rowCount() > 0)
    m_options->removeRow(0);
  Exporter* exporter = m_host->exporter(m_plugin->currentData().toString());
  if (!exporter)
    return;
  for (const ExporterOption& option : exporter->options()) {
    QWidget* editor = nullptr;
    switch (option.type) {
    case ExporterOption::Bool: {
      auto* box = new QCheckBox(m_optionsBox);
      box->setChecked(option.defaultValue.toBool());
      editor = box;
      break;
    }
    case ExporterOption::Int: {
      auto* spin = new QSpinBox(m_optionsBox);
      spin->setRange(option.minimum.isValid() ? option.minimum.toInt() : std::numeric_limits<int>::min(),
                     option.maximum.isValid() ? option.maximum.toInt() : std::numeric_limits<int>::max());
      spin->setValue(option.defaultValue.toInt());
      editor = spin;
      break;
    }
    case ExporterOption::Double: {
      auto* spin = new QDoubleSpinBox(m_optionsBox);
      spin->setDecimals(6);
      spin->setRange(option.minimum.isValid() ? option.minimum.toDouble() : -1e12,
                     option.maximum.isValid() ? option.maximum.toDouble() : 1e12);
      spin->setValue(option.defaultValue.toDouble());
      editor = spin;
      break;
    }
    case ExporterOption::String: {
      auto* line = new QLineEdit(option.defaultValue.toString(), m_optionsBox);
      editor = line;
      break;
    }
    case ExporterOption::Choice: {
      auto* combo = new QComboBox(m_optionsBox);
      combo->addItems(option.choices);
      combo->setCurrentText(option.defaultValue.toString());
      editor = combo;
      break;
    }
    }
    // Any change of an option makes the last result stale.
    if (auto* box = qobject_cast<QCheckBox*>(editor))
      connect(box, &QCheckBox::toggled, m_result, &QLabel::clear);
    else if (auto* spin = qobject_cast<QSpinBox*>(editor))
      connect(spin, &QSpinBox::valueChanged, m_result, &QLabel::clear);
    else if (auto* dspin = qobject_cast<QDoubleSpinBox*>(editor))
      connect(dspin, &QDoubleSpinBox::valueChanged, m_result, &QLabel::clear);
    else if (auto* line = qobject_cast<QLineEdit*>(editor))
      connect(line, &QLineEdit::textEdited, m_result, &QLabel::clear);
    else if (auto* combo = qobject_cast<QComboBox*>(editor))
      connect(combo, &QComboBox::currentIndexChanged, m_result, &QLabel::clear);
    editor->setObjectName(QStringLiteral("option_") + option.key);
    editor->setToolTip(option.help);
    auto* label = new QLabel(option.key + ':', m_optionsBox);
    label->setToolTip(option.help);
    m_options->addRow(label, editor);
  }
}

bool ExportDialog::currentOptions(QVariantMap* out_values, QString* out_error) const {
  Exporter* exporter = m_host->exporter(m_plugin->currentData().toString());
  if (!exporter) {
    if (out_error)
      *out_error = tr("no exporter plugin chosen");
    return false;
  }
  QVariantMap values;
  for (const ExporterOption& option : exporter->options()) {
    QWidget* editor = optionWidget(option.key);
    if (auto* box = qobject_cast<QCheckBox*>(editor))
      values.insert(option.key, box->isChecked());
    else if (auto* spin = qobject_cast<QSpinBox*>(editor))
      values.insert(option.key, spin->value());
    else if (auto* dspin = qobject_cast<QDoubleSpinBox*>(editor))
      values.insert(option.key, dspin->value());
    else if (auto* line = qobject_cast<QLineEdit*>(editor))
      values.insert(option.key, line->text());
    else if (auto* combo = qobject_cast<QComboBox*>(editor))
      values.insert(option.key, combo->currentText());
  }
  return checkExporterOptions(exporter->options(), values, out_values, out_error);
}

void ExportDialog::browse() {
  QStringList patterns;
  for (const PluginInfo& info : m_host->plugins())
    if (info.id == m_plugin->currentData().toString())
      for (const QString& suffix : info.suffixes)
        patterns << QStringLiteral("*.") + suffix;
  const QString path = QFileDialog::getSaveFileName(this, tr("Export to"), m_output->text(),
                                                    tr("%1 (%2)").arg(m_plugin->currentText(), patterns.join(' ')));
  if (!path.isEmpty())
    m_output->setText(path);
}

void ExportDialog::showResult(bool ok, const QString& message) {
  m_result->setText(ok ? message : QStringLiteral("<span style='color:#b00020'>%1</span>").arg(message));
}

void ExportDialog::startExport() {
  if (m_running)
    return showResult(false, tr("An export is running."));
  if (m_asset < 0)
    return showResult(false, tr("Nothing to export: import a character or a motion first."));
  Exporter* exporter = m_host->exporter(m_plugin->currentData().toString());
  if (!exporter)
    return showResult(false, tr("Choose an exporter plugin."));
  QString path = m_output->text().trimmed();
  if (path.isEmpty())
    return showResult(false, tr("Choose the output file."));
  // The file's suffix says its format: none gets the plugin's; another format's is refused
  // (a .glb written as a runtime bundle would mislead every tool that opens it).
  // (the CLI refuses what this refuses: sdk's hasSuffix())
  const QStringList suffixes = exporter->suffixes();
  const QString suffix = QFileInfo(path).suffix();
  if (suffix.isEmpty() && !suffixes.isEmpty()) {
    path = withSuffix(path, suffixes.first(), suffixes);
    m_output->setText(path);
  } else if (!suffixes.isEmpty() && !hasSuffix(path, suffixes)) {
    return showResult(false, tr("%1 ends in .%2, which is not what %3 writes (%4): change the file's suffix or "
                                "the plugin.")
                                 .arg(QFileInfo(path).fileName().toHtmlEscaped(), suffix.toHtmlEscaped(),
                                      m_plugin->currentText().toHtmlEscaped(), suffixesText(suffixes).toHtmlEscaped()));
  }
  QVariantMap options;
  QString error;
  if (!currentOptions(&options, &error))
    return showResult(false, error.toHtmlEscaped());
  std::vector<int> levels;
  for (int i = 0; i < m_levels->count(); ++i)
    if (m_levels->item(i)->checkState() == Qt::Checked)
      levels.push_back(i);
  if (levels.empty())
    return showResult(false, tr("Tick at least one level."));
  for (int i = 0; i < m_document->assetCount(); ++i)
    if (!m_document->asset(i) && i == m_asset)
      return showResult(false, tr("The character's file is missing: relink it first."));

  // What the worker needs, copied or shared: the project and the imported assets.
  std::vector<std::shared_ptr<const Asset>> assets;
  for (int i = 0; i < m_document->assetCount(); ++i)
    assets.push_back(m_document->asset(i));
  // what the format cannot hold is refused before minutes of building (as the CLI does)
  std::vector<const Asset*> importedNow;
  for (const std::shared_ptr<const Asset>& a : assets)
    importedNow.push_back(a.get());
  if (const QString problem = exporter->planProblem(packagePlan(m_document->project(), importedNow, m_asset, levels));
      !problem.isEmpty())
    return showResult(false, tr("Nothing was written: the %1 exporter cannot hold this character: %2")
                                 .arg(m_plugin->currentText().toHtmlEscaped(), problem.toHtmlEscaped()));
  m_cancel = std::make_shared<std::atomic<bool>>(false);
  m_running = true;
  m_exporting = m_document;
  m_document->beginWaitedJob(); // the views' background builds wait (Document::isWaitedJobRunning())
  m_runningPath = path;
  m_exportButton->setEnabled(false);
  m_result->clear();
  QSettings().setValue("export/plugin", m_plugin->currentData().toString());
  QSettings().setValue("export/lastDir", QFileInfo(path).absolutePath());

  m_progress = new QProgressDialog(tr("Building the LOD package…"), tr("Cancel"), 0, 1000, this);
  m_progress->setObjectName("exportProgress");
  m_progress->setWindowTitle(tr("Export"));
  m_progress->setWindowModality(Qt::WindowModal);
  m_progress->setMinimumDuration(0);
  m_progress->setAutoClose(false);
  m_progress->setAutoReset(false);
  m_progress->setValue(0);
  const std::shared_ptr<std::atomic<bool>> cancel = m_cancel;
  connect(m_progress, &QProgressDialog::canceled, this, [cancel] { cancel->store(true); });

  // Progress from the worker: queued to the dialog (a QPointer guards a closed dialog).
  QPointer<QProgressDialog> progress = m_progress;
  const auto report = [progress](double fraction, const QString& text) {
    QMetaObject::invokeMethod(
        progress,
        [progress, fraction, text] {
          if (progress && !progress->wasCanceled()) {
            progress->setValue(int(fraction * 1000.0));
            progress->setLabelText(text);
          }
        },
        Qt::QueuedConnection);
  };
  m_watcher.setFuture(QtConcurrent::run(&m_pool, [project = m_document->project(), assets, asset = m_asset, levels, exporter,
                                         path, options, cancel, report, hook = m_hook]() {
    if (hook)
      hook(*cancel);
    std::vector<const Asset*> imported;
    for (const std::shared_ptr<const Asset>& a : assets)
      imported.push_back(a.get());
    // building the package is most of the work: 0 .. 0.8; the plugin 0.8 .. 1
    Result<LodPackage> package = buildLodPackage(
        project, imported, asset, levels, [&](double fraction, std::string_view message) {
          report(0.8 * fraction, QString::fromUtf8(message.data(), qsizetype(message.size())));
          return !cancel->load();
        },
        cancel.get());
    if (!package)
      return std::make_shared<ExportResult>(package.message() == kLodPackageCancelled
                                                ? cancelledResult()
                                                : ExportResult::failure(QString::fromStdString(package.message())));
    if (cancel->load())
      return std::make_shared<ExportResult>(cancelledResult());
    return std::make_shared<ExportResult>(exporter->exportPackage(
        *package, path, options,
        ExportProgress([&](double fraction, const QString& text) { report(0.8 + 0.2 * fraction, text); },
                       [&] { return cancel->load(); })));
  }));
}

void ExportDialog::onFinished() {
  const std::shared_ptr<ExportResult> result = m_watcher.result();
  m_running = false;
  if (m_exporting)
    m_exporting->endWaitedJob();
  m_exporting.clear();
  m_exportButton->setEnabled(true);
  if (m_progress) {
    m_progress->deleteLater();
    m_progress = nullptr;
  }
  const bool ok = result && result->ok;
  const QString message = result ? result->message : tr("no result");
  if (ok) {
    const QString folder = QFileInfo(m_runningPath).absolutePath();
    showResult(true, tr("%1<br>In <a href=\"%2\">%3</a>")
                         .arg(message.toHtmlEscaped(), QUrl::fromLocalFile(folder).toString(), folder.toHtmlEscaped()));
  } else {
    showResult(false, tr("Nothing was written: %1").arg(message.toHtmlEscaped()));
  }
  emit exportFinished(ok, message);
}

} // namespace mlod
