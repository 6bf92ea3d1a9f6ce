#include "editor/models/mapping_model.h"

#include "editor/document/document.h"
#include "editor/document/edits.h"

#include <QComboBox>
#include <QFont>

namespace mlod {

MappingModel::MappingModel(Document* document, int mapping, QObject* parent)
    : DocumentTableModel(parent), m_document(document), m_mapping(mapping) {
  syncRows();
  connect(document, &Document::mappingsChanged, this, &MappingModel::refresh);
  connect(document, &Document::assetsChanged, this, &MappingModel::refresh);
}

const ProjectMapping* MappingModel::current() const {
  const auto& mappings = m_document->project().mappings;
  if (m_mapping < 0 || m_mapping >= static_cast<int>(mappings.size()))
    return nullptr;
  const ProjectMapping& mapping = mappings[static_cast<std::size_t>(m_mapping)];
  if (mapping.motion >= m_document->assetCount() || mapping.character >= m_document->assetCount() ||
      !m_document->asset(mapping.motion) || !m_document->asset(mapping.character))
    return nullptr;
  return &mapping;
}

QString MappingModel::characterJoint(int row) const {
  const ProjectMapping* mapping = current();
  return mapping ? QString::fromStdString(
                       m_document->asset(mapping->character)->skeleton.joints[static_cast<std::size_t>(row)].name)
                 : QString();
}

QStringList MappingModel::motionJoints() const {
  QStringList names{QString()};
  if (const ProjectMapping* mapping = current())
    for (const Joint& joint : m_document->asset(mapping->motion)->skeleton.joints)
      names << QString::fromStdString(joint.name);
  return names;
}

int MappingModel::rowCount(const QModelIndex& parent) const {
  const ProjectMapping* mapping = current();
  return parent.isValid() || !mapping ? 0 : m_document->asset(mapping->character)->skeleton.jointCount();
}

int MappingModel::columnCount(const QModelIndex& parent) const { return parent.isValid() ? 0 : ColumnCount; }

QVariant MappingModel::data(const QModelIndex& index, int role) const {
  const ProjectMapping* mapping = current();
  if (!index.isValid() || !mapping || index.row() >= rowCount())
    return {};
  const QString character = characterJoint(index.row());
  const std::string* motion = mapping->mapping.motionFor(character.toStdString());
  switch (role) {
  case Qt::DisplayRole:
    if (index.column() == CharacterColumn)
      return character;
    return motion ? QString::fromStdString(*motion) : tr("(none: rest pose)");
  case Qt::EditRole:
    if (index.column() == CharacterColumn)
      return character;
    return motion ? QString::fromStdString(*motion) : QString();
  case Qt::ForegroundRole:
    if (index.column() == MotionColumn && !motion)
      return QColor(Qt::gray);
    return {};
  case Qt::ToolTipRole:
    return index.column() == MotionColumn
               ? tr("The motion joint that drives %1; (none) keeps its rest pose. Double-click or F2 to change")
                     .arg(character)
               : tr("A joint of the character's skeleton");
  default: return {};
  }
}

bool MappingModel::setData(const QModelIndex& index, const QVariant& value, int role) {
  if (!index.isValid() || role != Qt::EditRole || index.column() != MotionColumn || !current())
    return false;
  return edit::setMappingPair(*m_document, m_mapping, characterJoint(index.row()), value.toString());
}

Qt::ItemFlags MappingModel::flags(const QModelIndex& index) const {
  Qt::ItemFlags flags = QAbstractTableModel::flags(index);
  if (index.isValid() && index.column() == MotionColumn)
    flags |= Qt::ItemIsEditable;
  return flags;
}

QVariant MappingModel::headerData(int section, Qt::Orientation orientation, int role) const {
  if (orientation != Qt::Horizontal || role != Qt::DisplayRole)
    return {};
  return section == CharacterColumn ? tr("Character joint") : tr("Motion joint");
}

QWidget* MappingDelegate::createEditor(QWidget* parent, const QStyleOptionViewItem& option, const QModelIndex& index) const {
  const auto* model = qobject_cast<const MappingModel*>(index.model());
  if (!model || index.column() != MappingModel::MotionColumn)
    return QStyledItemDelegate::createEditor(parent, option, index);
  auto* box = new QComboBox(parent);
  box->setObjectName("motionJointEditor");
  for (const QString& name : model->motionJoints())
    box->addItem(name.isEmpty() ? tr("(none)") : name, name);
  return box;
}

void MappingDelegate::setEditorData(QWidget* editor, const QModelIndex& index) const {
  if (auto* box = qobject_cast<QComboBox*>(editor)) {
    box->setCurrentIndex(std::max(0, box->findData(index.data(Qt::EditRole).toString())));
    return;
  }
  QStyledItemDelegate::setEditorData(editor, index);
}

void MappingDelegate::setModelData(QWidget* editor, QAbstractItemModel* model, const QModelIndex& index) const {
  if (auto* box = qobject_cast<QComboBox*>(editor)) {
    model->setData(index, box->currentData().toString(), Qt::EditRole);
    return;
  }
  QStyledItemDelegate::setModelData(editor, model, index);
}

} // namespace mlod
