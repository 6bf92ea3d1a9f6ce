#include "editor/views/budget_dialog.h"

#include "editor/document/level_generator.h"
#include "editor/views/job_progress.h"

#include <QComboBox>
#include <QDialogButtonBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QHeaderView>
#include <QLabel>
#include <QListWidget>
#include <QLocale>
#include <QPushButton>
#include <QSpinBox>
#include <QTableWidget>
#include <QVBoxLayout>
#include <cmath>

namespace mlod {

namespace {

QString threshold(double e) {
  return QString::number(e, 'f', e == std::floor(e) ? 0 : 1);
}

QTableWidgetItem* cell(const QString& text, Qt::Alignment alignment = Qt::AlignRight | Qt::AlignVCenter) {
  auto* item = new QTableWidgetItem(text);
  item->setFlags(Qt::ItemIsEnabled | Qt::ItemIsSelectable);
  item->setTextAlignment(alignment);
  return item;
}

} // namespace

BudgetDialog::BudgetDialog(LevelGenerator* generator, const BudgetRequest& initial, QWidget* parent)
    : QDialog(parent), m_generator(generator) {
  setObjectName("budgetDialog");
  setWindowTitle(tr("Generate Levels from Pixel Budget"));

  m_pixels = new QDoubleSpinBox;
  m_pixels->setObjectName("pixelsBox");
  m_pixels->setRange(0.01, 100.0);
  m_pixels->setDecimals(2);
  m_pixels->setSingleStep(0.25);
  m_pixels->setSuffix(tr(" px"));
  m_pixels->setToolTip(tr("The most any level may stray from the original on screen, motion and mesh together"));
  m_levels = new QSpinBox;
  m_levels->setObjectName("levelsBox");
  m_levels->setRange(1, 12);
  m_levels->setToolTip(tr("Levels to aim at, the original included: level i at 1/2^i of the screen height. Levels "
                          "that would repeat the one before, or keep the original motion, are left out"));
  m_fov = new QDoubleSpinBox;
  m_fov->setObjectName("fovBox");
  m_fov->setRange(1.0, 179.0);
  m_fov->setDecimals(1);
  m_fov->setSuffix(tr("°"));
  m_fov->setToolTip(tr("The camera's vertical field of view the pixel figures assume"));
  m_height = new QSpinBox;
  m_height->setObjectName("heightBox");
  m_height->setRange(1, 16384);
  m_height->setSuffix(tr(" px"));
  m_height->setToolTip(tr("The viewport's height in pixels the pixel figures assume"));
  m_skinning = new QComboBox;
  m_skinning->setObjectName("skinningBox");
  m_skinning->addItem(tr("GPU (the CPU poses)"), QString::fromLatin1(lodSkinningName(LodSkinning::Gpu)));
  m_skinning->addItem(tr("CPU (the CPU poses and skins)"), QString::fromLatin1(lodSkinningName(LodSkinning::Cpu)));
  m_skinning->setToolTip(
      tr("Where the character is skinned, which decides how each level's deviation is split between motion and "
         "mesh. GPU (as engines do): the CPU pays the pose alone and the motion takes half of each level's "
         "deviation. CPU: the motion takes its share of the frame cost, pose against CPU skinning (5% for "
         "54 joints and 3,014 vertices), so the mesh gets nearly all of it"));
  m_character = new QLabel;
  m_character->setObjectName("budgetCharacterLabel");
  m_character->setText(initial.character.isEmpty()
                           ? QString()
                           : tr("Levels of <b>%1</b> (its own LOD set)").arg(initial.character.toHtmlEscaped()));
  m_character->setVisible(!initial.character.isEmpty());
  auto* form = new QFormLayout;
  form->addRow(tr("Pixel error:"), m_pixels);
  form->addRow(tr("Levels (the original included):"), m_levels);
  form->addRow(tr("Vertical field of view:"), m_fov);
  form->addRow(tr("Viewport height:"), m_height);
  form->addRow(tr("Skinning on:"), m_skinning);

  m_table = new QTableWidget(0, ColumnCount);
  m_table->setObjectName("budgetPreview");
  const QStringList headers = {tr("Level"),        tr("E (cm·°)"),  tr("Mesh ratio"), tr("Switch at (m)"),
                               tr("Simplified %"), tr("Triangles"), tr("Joints")};
  const QStringList tips = {
      tr("The level's name"),
      tr("Motion threshold E, cm·degrees"),
      tr("Triangles kept of the original mesh"),
      tr("Camera distance from which the level is used, metres"),
      tr("Clustered joint-frames, % of clusterable joint-frames over every clip the level plays (the paper's Table 1)"),
      tr("Triangles of the level's mesh"),
      tr("Joints left after bone reduction")};
  m_table->setHorizontalHeaderLabels(headers);
  for (int c = 0; c < ColumnCount; ++c)
    m_table->horizontalHeaderItem(c)->setToolTip(tips[c]);
  m_table->verticalHeader()->hide();
  m_table->setEditTriggers(QAbstractItemView::NoEditTriggers);
  m_table->setSelectionMode(QAbstractItemView::NoSelection);
  m_table->horizontalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
  m_table->horizontalHeader()->setStretchLastSection(false);

  m_notes = new QLabel;
  m_notes->setObjectName("budgetNotes");
  m_notes->setWordWrap(true);
  m_notes->hide();
  m_overridesTitle = new QLabel;
  m_overridesTitle->setObjectName("overridesTitle");
  m_overridesTitle->setWordWrap(true);
  m_overrides = new QListWidget;
  m_overrides->setObjectName("overridesList");
  m_overrides->setMaximumHeight(90);
  m_overrides->hide();
  m_status = new QLabel;
  m_status->setObjectName("budgetStatus");
  m_status->setWordWrap(true);

  m_buttons = new QDialogButtonBox;
  m_previewButton = m_buttons->addButton(tr("Preview"), QDialogButtonBox::ActionRole);
  m_previewButton->setObjectName("previewButton");
  m_previewButton->setToolTip(tr("Compute the preview again now"));
  m_apply = m_buttons->addButton(tr("Apply"), QDialogButtonBox::AcceptRole);
  m_apply->setObjectName("applyButton");
  m_apply->setToolTip(tr("Replace the LOD levels with the previewed ones (one undo step)"));
  m_apply->setEnabled(false);
  m_buttons->addButton(QDialogButtonBox::Cancel)->setObjectName("cancelButton");
  connect(m_previewButton, &QPushButton::clicked, this, [this] {
    m_settle.stop();
    runPreview();
  });
  connect(m_apply, &QPushButton::clicked, this, &BudgetDialog::applyPlan);
  connect(m_buttons, &QDialogButtonBox::rejected, this, &BudgetDialog::reject);

  auto* layout = new QVBoxLayout(this);
  layout->addWidget(m_character);
  layout->addLayout(form);
  layout->addWidget(m_table, 1);
  layout->addWidget(m_notes);
  layout->addWidget(m_overridesTitle);
  layout->addWidget(m_overrides);
  layout->addWidget(m_status);
  layout->addWidget(m_buttons);
  resize(720, 520);

  m_progress = new JobProgress(tr("LOD levels"), tr("Cancel"), this);
  m_progress->setObjectName("budgetProgress");
  connect(m_progress, &QProgressDialog::canceled, this, [this] {
    if (m_previewing)
      m_generator->cancel(); // previewed(false, "cancelled") follows at once
  });
  connect(m_generator, &LevelGenerator::progressed, this, [this](int percent) {
    if (!m_previewing)
      return;
    m_progress->step(percent, 100);
    m_status->setText(tr("Previewing the levels … %1%").arg(percent));
  });
  connect(m_generator, &LevelGenerator::previewed, this, &BudgetDialog::onPreviewed);

  m_settle.setSingleShot(true);
  m_settle.setInterval(kSettleMs);
  connect(&m_settle, &QTimer::timeout, this, &BudgetDialog::runPreview);
  setRequest(initial);
  connect(m_pixels, &QDoubleSpinBox::valueChanged, this, &BudgetDialog::valuesChanged);
  connect(m_levels, &QSpinBox::valueChanged, this, &BudgetDialog::valuesChanged);
  connect(m_fov, &QDoubleSpinBox::valueChanged, this, &BudgetDialog::valuesChanged);
  connect(m_height, &QSpinBox::valueChanged, this, &BudgetDialog::valuesChanged);
  connect(m_skinning, &QComboBox::currentIndexChanged, this, &BudgetDialog::valuesChanged);
  valuesChanged();
}

BudgetDialog::~BudgetDialog() {
  if (m_previewing) {
    m_previewing = false;
    m_generator->cancel();
  }
}

BudgetRequest BudgetDialog::request() const {
  BudgetRequest out;
  out.pixels = m_pixels->value();
  out.levels = m_levels->value();
  out.projection.verticalFovDegrees = m_fov->value();
  out.projection.viewportHeightPixels = m_height->value();
  out.skinning = lodSkinningFromName(m_skinning->currentData().toString().toStdString()).value_or(LodSkinning::Gpu);
  return out;
}

void BudgetDialog::setRequest(const BudgetRequest& request) {
  m_pixels->setValue(request.pixels);
  m_levels->setValue(request.levels);
  m_fov->setValue(request.projection.verticalFovDegrees);
  m_height->setValue(static_cast<int>(std::lround(request.projection.viewportHeightPixels)));
  m_skinning->setCurrentIndex(m_skinning->findData(QString::fromLatin1(lodSkinningName(request.skinning))));
}

void BudgetDialog::valuesChanged() {
  m_current = false;
  m_apply->setEnabled(false);
  if (m_previewing) { // superseded: its result would show other values
    m_previewing = false;
    m_generator->cancel();
    m_progress->finish();
  }
  m_status->setText(tr("Previewing the levels …"));
  m_settle.start();
}

void BudgetDialog::runPreview() {
  if (m_previewing)
    return;
  if (m_generator->isBusy() || m_generator->isRunning()) { // a cancelled worker still ends: soon
    m_settle.start();
    return;
  }
  const BudgetRequest wanted = request();
  QString error;
  if (!m_generator->preview(wanted.pixels, wanted.levels, wanted.projection, wanted.skinning, &error)) {
    m_status->setText(tr("Cannot preview: %1").arg(error));
    return;
  }
  m_previewing = true;
  m_current = false;
  m_apply->setEnabled(false);
  m_status->setText(tr("Previewing the levels …"));
  m_progress->begin(tr("Previewing %1 levels within %2 px …").arg(wanted.levels).arg(wanted.pixels), 100);
}

void BudgetDialog::onPreviewed(bool ok, const QString& message) {
  if (!m_previewing)
    return; // superseded by a change of values, or not ours
  m_previewing = false;
  m_progress->finish();
  if (!ok) {
    m_table->setRowCount(0);
    m_notes->hide();
    m_overrides->hide();
    m_overridesTitle->clear();
    m_status->setText(message == tr("cancelled")
                          ? tr("Preview cancelled; the levels are as they were. Press Preview to compute it.")
                          : tr("Cannot generate the levels: %1").arg(message));
    return;
  }
  showPlan();
  m_current = true;
  m_apply->setEnabled(true);
  emit previewShown();
}

void BudgetDialog::showPlan() {
  const LevelPlan& plan = m_generator->plan();
  const std::vector<LodLevel>& levels = plan.lods.levels;
  m_table->setRowCount(static_cast<int>(levels.size()));
  for (std::size_t i = 0; i < levels.size(); ++i) {
    const LodLevel& level = levels[i];
    const int row = static_cast<int>(i);
    const double simplified = i < plan.report.simplifiedPercent.size() ? plan.report.simplifiedPercent[i] : 0.0;
    m_table->setItem(row, LevelColumn, cell(QString::fromStdString(level.name), Qt::AlignLeft | Qt::AlignVCenter));
    m_table->setItem(row, ThresholdColumn, cell(threshold(level.motionThreshold)));
    m_table->setItem(row, RatioColumn, cell(QString::number(level.meshRatio, 'f', 2)));
    m_table->setItem(row, DistanceColumn, cell(QString::number(level.switchDistanceCm / 100.0, 'f', 2)));
    m_table->setItem(row, SimplifiedColumn, cell(QString::number(simplified, 'f', 1)));
    m_table->setItem(row, TrianglesColumn, cell(level.triangles > 0 ? QLocale().toString(level.triangles) : tr("—")));
    m_table->setItem(row, JointsColumn, cell(QString::number(level.activeJoints)));
  }
  QStringList notes;
  for (const std::string& line : plan.report.dropped)
    notes << QString::fromStdString(line);
  m_notes->setText(notes.join('\n'));
  m_notes->setVisible(!notes.isEmpty());
  // Each override named with its asset (a motion mapped onto the character plays with its
  // levels too), its level and that level's E: an override applies at its own level only.
  m_overrides->clear();
  int above = 0;
  for (const LodOverrideAbove& o : plan.overrides) {
    const QString joint = o.asset.empty()
                              ? QString::fromStdString(o.joint)
                              : tr("%1 › %2").arg(QString::fromStdString(o.asset), QString::fromStdString(o.joint));
    if (o.beyond) {
      m_overrides->addItem(tr("%1 at level %2: %3 cm·° — these levels end at %4: dropped with Apply")
                               .arg(joint)
                               .arg(o.level)
                               .arg(threshold(o.overrideThreshold), QString::fromStdString(levels.back().name)));
      continue;
    }
    ++above;
    const QString name = QString::fromStdString(levels[static_cast<std::size_t>(o.level)].name);
    m_overrides->addItem(tr("%1 at %2: %3 cm·° — above %2's E of %4 cm·°")
                             .arg(joint, name, threshold(o.overrideThreshold), threshold(o.levelThreshold)));
  }
  m_overrides->setVisible(!plan.overrides.empty());
  const int dropped = static_cast<int>(plan.overrides.size()) - above;
  const QString overrides =
      plan.overrideCount == 1 ? tr("1 per-joint override") : tr("%1 per-joint overrides").arg(plan.overrideCount);
  QString title;
  if (plan.overrideCount == 0)
    title = tr("No per-joint override: every joint takes its level's E.");
  else if (plan.overrides.empty())
    title = tr("Of the %1, none is above the E of its own level here.").arg(overrides);
  else if (dropped == 0)
    title = tr("Of the %1, %2 above the E of their own level, kept as they are (edit them in the Skeleton dock):")
                .arg(overrides)
                .arg(above);
  else
    title = tr("Of the %1, %2 above the E of their own level (kept as they are) and %3 at levels these levels do not "
               "have (dropped with Apply):")
                .arg(overrides)
                .arg(above)
                .arg(dropped);
  m_overridesTitle->setText(title);
  const QString why = plan.lods.skinning == LodSkinning::Gpu ? tr("skinned on the GPU, the CPU pays the pose alone")
                                                             : tr("its share of the frame cost, skinned on the CPU");
  const QString share = plan.report.motionShare > 0.0 && plan.report.motionShare < 1.0
                            ? tr(" The motion takes %1% of each level's deviation (%2), the mesh the rest.")
                                  .arg(QString::number(100.0 * plan.report.motionShare, 'f', 0), why)
                            : QString();
  m_status->setText(tr("Levels within %1 px: %2.%3 Apply replaces the current levels (one undo step).")
                        .arg(plan.pixels)
                        .arg(levels.size())
                        .arg(share));
}

void BudgetDialog::applyPlan() {
  if (!m_current)
    return;
  QString error;
  if (!m_generator->apply(&error)) {
    m_status->setText(tr("Cannot apply: %1").arg(error));
    return;
  }
  accept();
}

void BudgetDialog::reject() {
  m_settle.stop();
  if (m_previewing) {
    m_previewing = false;
    m_generator->cancel();
    m_progress->finish();
  }
  QDialog::reject();
}

} // namespace mlod
