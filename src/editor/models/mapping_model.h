#pragma once
// The joint-mapping table of one motion assigned to a character (docs/architecture.md section 3,
// MotionMapping): one row per character joint, the motion joint that drives it beside it.
// Edits go through the Document (one undo command each); the model follows the project, so
// undo and redo show in the table.

#include "editor/models/document_table_model.h"

#include <QStyledItemDelegate>

namespace mlod {

class Document;

class MappingModel : public DocumentTableModel {
  Q_OBJECT
public:
  enum Column { CharacterColumn, MotionColumn, ColumnCount };
  // `mapping`: an index into the project's mappings.
  MappingModel(Document* document, int mapping, QObject* parent = nullptr);

  int mapping() const { return m_mapping; }
  QStringList motionJoints() const; // the names a motion cell can take ("" first: none)

  int rowCount(const QModelIndex& parent = {}) const override;
  int columnCount(const QModelIndex& parent = {}) const override;
  QVariant data(const QModelIndex& index, int role = Qt::DisplayRole) const override;
  bool setData(const QModelIndex& index, const QVariant& value, int role = Qt::EditRole) override;
  Qt::ItemFlags flags(const QModelIndex& index) const override;
  QVariant headerData(int section, Qt::Orientation orientation, int role = Qt::DisplayRole) const override;

private:
  const struct ProjectMapping* current() const; // null when the mapping is gone (undone)
  QString characterJoint(int row) const;

  Document* m_document;
  int m_mapping;
};

// A combo box of the motion's joints ("(none)" first) for the motion column.
class MappingDelegate : public QStyledItemDelegate {
  Q_OBJECT
public:
  using QStyledItemDelegate::QStyledItemDelegate;
  QWidget* createEditor(QWidget* parent, const QStyleOptionViewItem& option, const QModelIndex& index) const override;
  void setEditorData(QWidget* editor, const QModelIndex& index) const override;
  void setModelData(QWidget* editor, QAbstractItemModel* model, const QModelIndex& index) const override;
};

} // namespace mlod
