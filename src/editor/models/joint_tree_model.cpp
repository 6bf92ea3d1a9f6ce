#include "editor/models/joint_tree_model.h"

#include "editor/document/document.h"
#include "editor/document/edits.h"
#include "editor/models/cell_editor.h"

#include <QDoubleSpinBox>
#include <QFont>

namespace mlod {

JointTreeModel::JointTreeModel(Document* document, QObject* parent) : QAbstractItemModel(parent), m_document(document) {
  connect(document, &Document::currentChanged, this, [this] {
    if (m_document->currentAssetPtr() != m_skeletonOf)
      rebuild();
    else
      refreshValues();
  });
  connect(document, &Document::assetsChanged, this, &JointTreeModel::rebuild);
  connect(document, &Document::settingsChanged, this, &JointTreeModel::refreshValues);
  connect(document, &Document::analysisFinished, this, &JointTreeModel::refreshValues);
  rebuild();
}

void JointTreeModel::rebuild() {
  beginResetModel();
  const Asset* asset = m_document->currentAssetPtr();
  m_skeletonOf = asset;
  m_children.clear();
  m_roots.clear();
  m_parents.clear();
  m_rowInParent.clear();
  if (asset) {
    const Skeleton& skeleton = asset->skeleton;
    m_children.resize(static_cast<std::size_t>(skeleton.jointCount()));
    for (int j = 0; j < skeleton.jointCount(); ++j) {
      const int parent = skeleton.joints[static_cast<std::size_t>(j)].parent;
      m_parents.push_back(parent);
      auto& siblings = parent < 0 ? m_roots : m_children[static_cast<std::size_t>(parent)];
      m_rowInParent.push_back(static_cast<int>(siblings.size()));
      siblings.push_back(j);
    }
  }
  endResetModel();
}

void JointTreeModel::refreshValues() {
  if (m_parents.empty())
    return;
  for (int j = 0; j < static_cast<int>(m_parents.size()); ++j)
    emit dataChanged(indexOfJoint(j, AlphaColumn), indexOfJoint(j, SimplifiedColumn));
  emit headerDataChanged(Qt::Horizontal, ThresholdColumn, SimplifiedColumn);
}

QModelIndex JointTreeModel::indexOfJoint(int joint, int column) const {
  if (joint < 0 || joint >= static_cast<int>(m_parents.size()))
    return {};
  return createIndex(m_rowInParent[static_cast<std::size_t>(joint)], column, static_cast<quintptr>(joint));
}

QModelIndex JointTreeModel::index(int row, int column, const QModelIndex& parent) const {
  const std::vector<int>& list = parent.isValid() ? m_children[static_cast<std::size_t>(jointAt(parent))] : m_roots;
  if (row < 0 || row >= static_cast<int>(list.size()) || column < 0 || column >= ColumnCount)
    return {};
  return createIndex(row, column, static_cast<quintptr>(list[static_cast<std::size_t>(row)]));
}

QModelIndex JointTreeModel::parent(const QModelIndex& child) const {
  if (!child.isValid())
    return {};
  return indexOfJoint(m_parents[static_cast<std::size_t>(jointAt(child))]);
}

int JointTreeModel::rowCount(const QModelIndex& parent) const {
  if (parent.isValid() && parent.column() != 0)
    return 0;
  return static_cast<int>(parent.isValid() ? m_children[static_cast<std::size_t>(jointAt(parent))].size() : m_roots.size());
}

int JointTreeModel::columnCount(const QModelIndex&) const { return ColumnCount; }

QVariant JointTreeModel::data(const QModelIndex& index, int role) const {
  const Asset* asset = m_document->currentAssetPtr();
  if (!index.isValid() || !asset)
    return {};
  const int joint = jointAt(index);
  const std::string& name = asset->skeleton.joints[static_cast<std::size_t>(joint)].name;
  const Project& project = m_document->project();
  const auto& joints = project.assets[static_cast<std::size_t>(m_document->currentAsset())].joints;
  const auto found = joints.find(name);
  const JointSettings settings = found != joints.end() ? found->second : JointSettings{};
  const Clip* clip = m_document->currentClipPtr();
  const bool clusterable = clip && clip->hasRotation[static_cast<std::size_t>(joint)] != 0;
  const int level = m_document->currentLevel();
  const double levelThreshold = m_document->lods().levels[static_cast<std::size_t>(level)].motionThreshold;
  const bool ownThreshold = level < static_cast<int>(settings.thresholds.size()) &&
                            settings.thresholds[static_cast<std::size_t>(level)].has_value();
  const double threshold = ownThreshold ? *settings.thresholds[static_cast<std::size_t>(level)] : levelThreshold;
  const double alpha = settings.alpha.value_or(project.alpha);
  const auto analysis = m_document->analysis();

  switch (role) {
  case Qt::DisplayRole:
    switch (index.column()) {
    case NameColumn: return QString::fromStdString(name);
    case AlphaColumn: return clusterable ? QString::number(alpha, 'g', 6) : QString();
    case ThresholdColumn: return clusterable ? QString::number(threshold, 'g', 6) : QString();
    case ImportanceColumn: return QString::number(settings.meshImportance, 'g', 4);
    case SimplifiedColumn:
      if (!clusterable || !analysis || level >= analysis->levelCount())
        return QString();
      return QString::number(analysis->levels[static_cast<std::size_t>(level)].joints[static_cast<std::size_t>(joint)].simplifiedPercent,
                             'f', 1);
    default: return {};
    }
  case Qt::EditRole:
    if (index.column() == AlphaColumn)
      return alpha;
    if (index.column() == ThresholdColumn)
      return threshold;
    if (index.column() == ImportanceColumn)
      return settings.meshImportance;
    return data(index, Qt::DisplayRole);
  case Qt::CheckStateRole:
    if (index.column() == LockColumn && clusterable)
      return settings.locked ? Qt::Checked : Qt::Unchecked;
    return {};
  case Qt::FontRole:
    if ((index.column() == AlphaColumn && settings.alpha) || (index.column() == ThresholdColumn && ownThreshold) ||
        (index.column() == ImportanceColumn && settings.meshImportance != 1.0)) {
      QFont bold;
      bold.setBold(true); // the joint's own value, not the project's or the level's
      return bold;
    }
    return {};
  case Qt::TextAlignmentRole:
    return index.column() == NameColumn ? QVariant() : QVariant(Qt::AlignRight | Qt::AlignVCenter);
  case Qt::ToolTipRole:
    if (index.column() == ImportanceColumn)
      return tr("Mesh importance of %1: the mesh LOD's cost of removing the vertices it moves is multiplied by it "
                "(raise it for the face or hands). Bold: not 1.")
          .arg(QString::fromStdString(name));
    if (!clusterable)
      return tr("%1 has no rotation channel in this clip (an end site): never clustered").arg(QString::fromStdString(name));
    switch (index.column()) {
    case AlphaColumn:
      return tr("Orientation weight α of %1, cm (%2). Bold: the joint's own.")
          .arg(QString::fromStdString(name), settings.alpha ? tr("its own") : tr("the project's"));
    case ThresholdColumn:
      return tr("Error threshold T at level %1, cm·degrees (E/57.3 ≈ cm). Bold: the joint's own; else the level's %2.")
          .arg(level)
          .arg(levelThreshold);
    case LockColumn: return tr("Locked joints are never simplified");
    case SimplifiedColumn: return tr("Frames in which the joint is frozen at a key posture, % of the clip, at level %1").arg(level);
    default: return QString::fromStdString(name);
    }
  default: return {};
  }
}

std::vector<int> JointTreeModel::targets(int joint) const {
  std::vector<int> joints = m_selection ? m_selection(joint) : std::vector<int>{};
  if (std::find(joints.begin(), joints.end(), joint) == joints.end())
    joints = {joint};
  return joints;
}

bool JointTreeModel::setData(const QModelIndex& index, const QVariant& value, int role) {
  if (!index.isValid())
    return false;
  const int joint = jointAt(index);
  if (role == Qt::CheckStateRole && index.column() == LockColumn) {
    edit::setJointsLocked(*m_document, targets(joint), value.toInt() == Qt::Checked);
    return true;
  }
  if (role != Qt::EditRole)
    return false;
  if (index.column() == ImportanceColumn) {
    bool ok = false;
    const double importance = value.toDouble(&ok);
    if (!ok || validateMeshImportance(importance))
      return false;
    edit::setJointMeshImportance(*m_document, targets(joint), importance);
    return true;
  }
  std::optional<double> number;
  if (!value.isNull() && !value.toString().isEmpty()) {
    bool ok = false;
    const double parsed = value.toDouble(&ok);
    if (!ok || !std::isfinite(parsed) || parsed < 0.0)
      return false;
    number = parsed;
  }
  if (index.column() == AlphaColumn)
    edit::setJointAlpha(*m_document, targets(joint), number);
  else if (index.column() == ThresholdColumn)
    edit::setJointThreshold(*m_document, targets(joint), m_document->currentLevel(), number);
  else
    return false;
  return true;
}

Qt::ItemFlags JointTreeModel::flags(const QModelIndex& index) const {
  if (!index.isValid())
    return Qt::NoItemFlags;
  Qt::ItemFlags flags = Qt::ItemIsEnabled | Qt::ItemIsSelectable;
  const Clip* clip = m_document->currentClipPtr();
  const bool clusterable = clip && clip->hasRotation[static_cast<std::size_t>(jointAt(index))] != 0;
  if (clusterable && index.column() == AlphaColumn)
    flags |= Qt::ItemIsEditable;
  if (clusterable && index.column() == ThresholdColumn && m_document->currentLevel() > 0)
    flags |= Qt::ItemIsEditable; // level 0 is the original: no threshold to override
  if (clusterable && index.column() == LockColumn)
    flags |= Qt::ItemIsUserCheckable;
  const Asset* asset = m_document->currentAssetPtr();
  if (index.column() == ImportanceColumn && asset && !asset->meshes.empty())
    flags |= Qt::ItemIsEditable; // a joint of a character with a mesh
  return flags;
}

QVariant JointTreeModel::headerData(int section, Qt::Orientation orientation, int role) const {
  if (orientation != Qt::Horizontal)
    return {};
  const int level = m_document->currentLevel();
  // Two lines where a unit follows the name, so the figures' columns stay as narrow as their
  // values and the joint names keep the width (the tooltips say the units in words).
  if (role == Qt::DisplayRole) {
    switch (section) {
    case NameColumn: return tr("Joint");
    case AlphaColumn:
      return tr("α\n(cm)");
    case ThresholdColumn:
      return tr("T L%1\n(cm·°)").arg(level);
    case LockColumn: return tr("Lock");
    case ImportanceColumn:
      return tr("Mesh\n×");
    case SimplifiedColumn:
      return tr("Simpl.\n% L%1").arg(level);
    default: return {};
    }
  }
  if (role == Qt::ToolTipRole) {
    switch (section) {
    case NameColumn:
      return tr(
          "The skeleton's joints; a name too long for the column is cut in the middle and shown whole in its tooltip");
    case AlphaColumn:
      return tr("α (cm): the orientation weight; one degree of twist counts like one degree of swing on an α cm "
                "segment. Bold: the joint's own, else the project's (LOD Levels dock)");
    case ThresholdColumn:
      return tr("T L%1 (cm·°): the error threshold at level %1, in cm·degrees (E/57.3 ≈ cm). Bold: the joint's own, "
                "else the level's E")
          .arg(level);
    case LockColumn:
      return tr("Lock: a locked joint is never simplified at any level");
    case ImportanceColumn:
      return tr("Mesh × (mesh importance): the mesh LOD's cost of removing the vertices the joint moves is multiplied "
                "by it; 1 = as any other joint, raise it for the face or hands");
    case SimplifiedColumn:
      return tr("Simpl. % L%1: frames in which the joint is frozen at a key posture, % of the clip, at level %1")
          .arg(level);
    default: return {};
    }
  }
  if (role == Qt::TextAlignmentRole && section == NameColumn)
    return QVariant(Qt::AlignLeft | Qt::AlignVCenter);
  return {};
}

QWidget* JointDelegate::createEditor(QWidget* parent, const QStyleOptionViewItem& option, const QModelIndex& index) const {
  if (index.column() == JointTreeModel::ImportanceColumn) {
    auto* box = new QDoubleSpinBox(parent);
    box->setObjectName("importanceEditor");
    box->setDecimals(2);
    box->setRange(0.1, 100.0);
    box->setSingleStep(0.5);
    box->setPrefix(QStringLiteral("×"));
    box->setFrame(false);
    box->setKeyboardTracking(false);
    return box;
  }
  if (index.column() != JointTreeModel::AlphaColumn && index.column() != JointTreeModel::ThresholdColumn)
    return QStyledItemDelegate::createEditor(parent, option, index);
  auto* box = new QDoubleSpinBox(parent);
  box->setObjectName(index.column() == JointTreeModel::AlphaColumn ? "alphaEditor" : "thresholdEditor");
  box->setDecimals(2);
  box->setRange(0.0, 100000.0);
  box->setSingleStep(index.column() == JointTreeModel::AlphaColumn ? 0.5 : 5.0);
  box->setSuffix(index.column() == JointTreeModel::AlphaColumn ? tr(" cm") : tr(" cm·°"));
  box->setFrame(false);
  box->setKeyboardTracking(false);
  return box;
}

void JointDelegate::setEditorData(QWidget* editor, const QModelIndex& index) const {
  if (auto* box = qobject_cast<QDoubleSpinBox*>(editor))
    box->setValue(index.data(Qt::EditRole).toDouble());
  else
    QStyledItemDelegate::setEditorData(editor, index);
}

void JointDelegate::setModelData(QWidget* editor, QAbstractItemModel* model, const QModelIndex& index) const {
  if (auto* box = qobject_cast<QDoubleSpinBox*>(editor)) {
    box->interpretText();
    if (box->value() != index.data(Qt::EditRole).toDouble())
      model->setData(index, box->value(), Qt::EditRole);
  } else {
    QStyledItemDelegate::setModelData(editor, model, index);
  }
}

void JointDelegate::updateEditorGeometry(QWidget* editor, const QStyleOptionViewItem& option,
                                         const QModelIndex&) const {
  placeCellEditor(editor, option);
}

} // namespace mlod
