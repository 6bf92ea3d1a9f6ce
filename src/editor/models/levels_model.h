#pragma once
// The LOD levels dock's model: one row per level of the project's LodSet with its name,
// motion threshold, mesh ratio and switch distance (each edit one undo command through the
// Document) and the clip's simplified % there. Level 0 is the original: only its name can
// be edited.

#include "editor/models/document_table_model.h"

#include <QStyledItemDelegate>

namespace mlod {

class Document;

class LevelsModel : public DocumentTableModel {
  Q_OBJECT
public:
  enum Column { NameColumn, ThresholdColumn, MeshRatioColumn, SwitchDistanceColumn, SimplifiedColumn, ColumnCount };
  explicit LevelsModel(Document* document, QObject* parent = nullptr);

  int rowCount(const QModelIndex& parent = {}) const override;
  int columnCount(const QModelIndex& parent = {}) const override;
  QVariant data(const QModelIndex& index, int role = Qt::DisplayRole) const override;
  bool setData(const QModelIndex& index, const QVariant& value, int role = Qt::EditRole) override;
  Qt::ItemFlags flags(const QModelIndex& index) const override;
  QVariant headerData(int section, Qt::Orientation orientation, int role = Qt::DisplayRole) const override;

signals:
  void editRefused(const QString& reason); // a value the level cannot take (for the log)

private:
  Document* m_document;
};

// Spin boxes with the units and ranges of each column (threshold cm·degrees, ratio (0, 1],
// distance cm); a line edit for the name.
class LevelDelegate : public QStyledItemDelegate {
  Q_OBJECT
public:
  using QStyledItemDelegate::QStyledItemDelegate;
  QWidget* createEditor(QWidget* parent, const QStyleOptionViewItem& option, const QModelIndex& index) const override;
  void setEditorData(QWidget* editor, const QModelIndex& index) const override;
  void setModelData(QWidget* editor, QAbstractItemModel* model, const QModelIndex& index) const override;
  // Over the cell, widened to the editor's size hint where the column is narrower (cell_editor.h).
  void updateEditorGeometry(QWidget* editor, const QStyleOptionViewItem& option,
                            const QModelIndex& index) const override;
};

} // namespace mlod
