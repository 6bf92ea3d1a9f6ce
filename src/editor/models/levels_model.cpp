#include "editor/models/levels_model.h"

#include "editor/document/document.h"

#include <QFont>

namespace mlod {

LevelsModel::LevelsModel(Document* document, QObject* parent) : QAbstractTableModel(parent), m_document(document) {
  const auto reset = [this] {
    beginResetModel();
    endResetModel();
  };
  connect(document, &Document::settingsChanged, this, reset);
  connect(document, &Document::currentChanged, this, reset);
  connect(document, &Document::analysisFinished, this, reset);
}

int LevelsModel::rowCount(const QModelIndex& parent) const {
  return parent.isValid() ? 0 : static_cast<int>(m_document->project().levelThresholds.size());
}

int LevelsModel::columnCount(const QModelIndex& parent) const { return parent.isValid() ? 0 : ColumnCount; }

QVariant LevelsModel::data(const QModelIndex& index, int role) const {
  if (!index.isValid())
    return {};
  const int level = index.row();
  const double threshold = m_document->project().levelThresholds[static_cast<std::size_t>(level)];
  const auto analysis = m_document->analysis();
  switch (role) {
  case Qt::DisplayRole:
    switch (index.column()) {
    case NameColumn: return tr("LOD %1").arg(level);
    case ThresholdColumn: return QString::number(threshold, 'g', 6);
    case SimplifiedColumn:
      return analysis && level < analysis->levelCount()
                 ? QString::number(analysis->levels[static_cast<std::size_t>(level)].simplifiedPercent, 'f', 1)
                 : QString();
    default: return {};
    }
  case Qt::EditRole: return index.column() == ThresholdColumn ? QVariant(threshold) : data(index, Qt::DisplayRole);
  case Qt::FontRole:
    if (level == m_document->currentLevel()) {
      QFont bold;
      bold.setBold(true); // the level every view shows
      return bold;
    }
    return {};
  case Qt::ToolTipRole:
    if (index.column() == ThresholdColumn)
      return tr("Motion error threshold E of the level, cm·degrees (E/57.3 ≈ cm); joints may override it");
    if (index.column() == SimplifiedColumn)
      return tr("Simplified joints of the clip in view at this level, % of joint-frames (the paper's Table 1)");
    return tr("Double-click a level to show it in every view");
  default: return {};
  }
}

bool LevelsModel::setData(const QModelIndex& index, const QVariant& value, int role) {
  if (!index.isValid() || role != Qt::EditRole || index.column() != ThresholdColumn)
    return false;
  bool ok = false;
  const double threshold = value.toDouble(&ok);
  if (!ok || !std::isfinite(threshold) || threshold < 0.0)
    return false;
  m_document->setLevelThreshold(index.row(), threshold);
  return true;
}

Qt::ItemFlags LevelsModel::flags(const QModelIndex& index) const {
  Qt::ItemFlags flags = QAbstractTableModel::flags(index);
  if (index.column() == ThresholdColumn)
    flags |= Qt::ItemIsEditable;
  return flags;
}

QVariant LevelsModel::headerData(int section, Qt::Orientation orientation, int role) const {
  if (orientation != Qt::Horizontal || role != Qt::DisplayRole)
    return {};
  switch (section) {
  case NameColumn: return tr("Level");
  case ThresholdColumn: return tr("E (cm·°)");
  case SimplifiedColumn: return tr("Simplified %");
  default: return {};
  }
}

} // namespace mlod
