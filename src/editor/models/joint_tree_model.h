#pragma once
// The Skeleton dock's model: the current asset's joints as a tree, with alpha, the threshold
// at the current level, the lock, the mesh importance and the simplified % at that level. Edits become document
// commands; an edit of a selected row applies to every selected row.

#include <QAbstractItemModel>
#include <QStyledItemDelegate>

#include <functional>
#include <vector>

namespace mlod {

class Document;

class JointTreeModel : public QAbstractItemModel {
  Q_OBJECT
public:
  enum Column {
    NameColumn,
    AlphaColumn,
    ThresholdColumn,
    LockColumn,
    ImportanceColumn,
    SimplifiedColumn,
    ColumnCount
  };
  explicit JointTreeModel(Document* document, QObject* parent = nullptr);

  // The joints an edit of `joint` applies to (the selection when it holds the joint).
  void setSelectionProvider(std::function<std::vector<int>(int joint)> provider) { m_selection = std::move(provider); }

  QModelIndex indexOfJoint(int joint, int column = 0) const;
  int jointAt(const QModelIndex& index) const { return index.isValid() ? static_cast<int>(index.internalId()) : -1; }

  QModelIndex index(int row, int column, const QModelIndex& parent = {}) const override;
  QModelIndex parent(const QModelIndex& child) const override;
  int rowCount(const QModelIndex& parent = {}) const override;
  int columnCount(const QModelIndex& parent = {}) const override;
  QVariant data(const QModelIndex& index, int role = Qt::DisplayRole) const override;
  bool setData(const QModelIndex& index, const QVariant& value, int role = Qt::EditRole) override;
  Qt::ItemFlags flags(const QModelIndex& index) const override;
  QVariant headerData(int section, Qt::Orientation orientation, int role = Qt::DisplayRole) const override;

private:
  void rebuild();
  void refreshValues();
  std::vector<int> targets(int joint) const;

  Document* m_document;
  std::vector<std::vector<int>> m_children; // per joint
  std::vector<int> m_roots;
  std::vector<int> m_parents;
  std::vector<int> m_rowInParent;
  const void* m_skeletonOf = nullptr;
  std::function<std::vector<int>(int)> m_selection;
};

// Spin boxes with units for alpha (cm) and threshold (cm·degrees); an empty value clears
// the joint's own setting (it falls back to the project's alpha or the level's threshold).
// The mesh importance takes a factor (0.1 to 100).
class JointDelegate : public QStyledItemDelegate {
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
