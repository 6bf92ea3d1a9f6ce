#include "editor/models/levels_model.h"

#include "editor/document/document.h"
#include "editor/document/edits.h"
#include "editor/models/cell_editor.h"

#include <QDoubleSpinBox>
#include <QFont>
#include <QLineEdit>

#include <cmath>

namespace mlod {

LevelsModel::LevelsModel(Document* document, QObject* parent) : DocumentTableModel(parent), m_document(document) {
  syncRows();
  connect(document, &Document::settingsChanged, this, &LevelsModel::refresh);
  connect(document, &Document::currentChanged, this, &LevelsModel::refresh);
  connect(document, &Document::analysisFinished, this, &LevelsModel::refresh);
}

int LevelsModel::rowCount(const QModelIndex& parent) const {
  return parent.isValid() ? 0 : m_document->levelCount();
}

int LevelsModel::columnCount(const QModelIndex& parent) const { return parent.isValid() ? 0 : ColumnCount; }

QVariant LevelsModel::data(const QModelIndex& index, int role) const {
  if (!index.isValid() || index.row() >= rowCount())
    return {};
  const int row = index.row();
  const LodLevel& level = m_document->lods().levels[static_cast<std::size_t>(row)];
  const auto analysis = m_document->analysis();
  switch (role) {
  case Qt::DisplayRole:
    switch (index.column()) {
    case NameColumn: return QString::fromStdString(level.name);
    case ThresholdColumn: return row == 0 ? tr("original") : QString::number(level.motionThreshold, 'g', 6);
    // one format a column: "40.0%", "72.10 m" and "0.00 m" (not "9.968%", "72.0976 m", "0 m")
    case MeshRatioColumn: return QString::number(level.meshRatio * 100.0, 'f', 1) + "%";
    case SwitchDistanceColumn: return QString::number(level.switchDistanceCm / 100.0, 'f', 2) + " m";
    case SimplifiedColumn:
      return analysis && row < analysis->levelCount()
                 ? QString::number(analysis->levels[static_cast<std::size_t>(row)].simplifiedPercent, 'f', 1)
                 : QString();
    default: return {};
    }
  case Qt::EditRole:
    switch (index.column()) {
    case NameColumn: return QString::fromStdString(level.name);
    case ThresholdColumn: return level.motionThreshold;
    case MeshRatioColumn: return level.meshRatio;
    case SwitchDistanceColumn: return level.switchDistanceCm;
    default: return data(index, Qt::DisplayRole);
    }
  case Qt::FontRole:
    if (row == m_document->currentLevel()) {
      QFont bold;
      bold.setBold(true); // the level every view shows
      return bold;
    }
    return {};
  case Qt::ToolTipRole:
    switch (index.column()) {
    case NameColumn: return tr("The level's name (unique). Double-click a row to show the level in every view; F2 renames");
    case ThresholdColumn:
      return row == 0 ? tr("Level 0 is the original motion: nothing is clustered")
                      : tr("Motion error threshold E of the level, cm·degrees (E/57.3 ≈ cm); joints may override it");
    case MeshRatioColumn: return tr("Triangles the level's mesh keeps, % of the original (0–100]");
    case SwitchDistanceColumn:
      return tr("Camera distance from which the level is used (edited in cm, shown in m); never nearer than the "
                "previous level's");
    case SimplifiedColumn:
      return tr("Simplified joints of the clip in view at this level, % of joint-frames (the paper's Table 1)");
    default: return {};
    }
  default: return {};
  }
}

bool LevelsModel::setData(const QModelIndex& index, const QVariant& value, int role) {
  if (!index.isValid() || role != Qt::EditRole)
    return false;
  const int row = index.row();
  QString reason;
  bool ok = false;
  switch (index.column()) {
  case NameColumn: ok = edit::renameLevel(*m_document, row, value.toString(), &reason); break;
  case ThresholdColumn: {
    const double threshold = value.toDouble(&ok);
    ok = ok && std::isfinite(threshold) && threshold >= 0.0 && row > 0;
    if (ok)
      edit::setLevelThreshold(*m_document, row, threshold);
    else
      reason = tr("a threshold is a number >= 0 cm·degrees, and level 0 has none");
    break;
  }
  case MeshRatioColumn: {
    const double ratio = value.toDouble(&ok);
    ok = ok && edit::setLevelMeshRatio(*m_document, row, ratio, &reason);
    break;
  }
  case SwitchDistanceColumn: {
    const double cm = value.toDouble(&ok);
    ok = ok && edit::setLevelSwitchDistance(*m_document, row, cm, &reason);
    break;
  }
  default: return false;
  }
  if (!ok)
    emit editRefused(tr("Level %1: %2").arg(row).arg(reason));
  return ok;
}

Qt::ItemFlags LevelsModel::flags(const QModelIndex& index) const {
  Qt::ItemFlags flags = QAbstractTableModel::flags(index);
  if (!index.isValid())
    return flags;
  const bool original = index.row() == 0; // the original keeps E 0, ratio 1, distance 0
  if (index.column() == NameColumn || (!original && index.column() != SimplifiedColumn))
    flags |= Qt::ItemIsEditable;
  return flags;
}

QVariant LevelsModel::headerData(int section, Qt::Orientation orientation, int role) const {
  if (orientation != Qt::Horizontal || role != Qt::DisplayRole)
    return {};
  switch (section) {
  case NameColumn: return tr("Level");
  case ThresholdColumn: return tr("E (cm·°)");
  case MeshRatioColumn: return tr("Mesh");
  case SwitchDistanceColumn: return tr("From");
  case SimplifiedColumn: return tr("Simplified %");
  default: return {};
  }
}

QWidget* LevelDelegate::createEditor(QWidget* parent, const QStyleOptionViewItem& option, const QModelIndex& index) const {
  auto spin = [parent](double low, double high, int decimals, double step, const QString& suffix) {
    auto* box = new QDoubleSpinBox(parent);
    box->setRange(low, high);
    box->setDecimals(decimals);
    box->setSingleStep(step);
    box->setSuffix(suffix);
    box->setFrame(false);
    return box;
  };
  switch (index.column()) {
  case LevelsModel::ThresholdColumn: return spin(0.0, 1e6, 2, 5.0, tr(" cm·°"));
  case LevelsModel::MeshRatioColumn: return spin(0.001, 1.0, 3, 0.05, QString()); // a fraction of the triangles
  case LevelsModel::SwitchDistanceColumn: return spin(0.0, 1e7, 1, 100.0, tr(" cm"));
  default: return QStyledItemDelegate::createEditor(parent, option, index);
  }
}

void LevelDelegate::setEditorData(QWidget* editor, const QModelIndex& index) const {
  if (auto* box = qobject_cast<QDoubleSpinBox*>(editor)) {
    box->setValue(index.data(Qt::EditRole).toDouble());
    return;
  }
  QStyledItemDelegate::setEditorData(editor, index);
}

void LevelDelegate::setModelData(QWidget* editor, QAbstractItemModel* model, const QModelIndex& index) const {
  if (auto* box = qobject_cast<QDoubleSpinBox*>(editor)) {
    box->interpretText();
    model->setData(index, box->value(), Qt::EditRole);
    return;
  }
  QStyledItemDelegate::setModelData(editor, model, index);
}

void LevelDelegate::updateEditorGeometry(QWidget* editor, const QStyleOptionViewItem& option,
                                         const QModelIndex&) const {
  placeCellEditor(editor, option);
}

} // namespace mlod
