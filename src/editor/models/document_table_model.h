#pragma once
// A table model that follows the Document. refresh() resets the model only when its row
// count changed and otherwise reports every cell changed: a reset in the middle of a
// delegate's commit would destroy the editor the view is still closing.

#include <QAbstractTableModel>

namespace mlod {

class DocumentTableModel : public QAbstractTableModel {
public:
  using QAbstractTableModel::QAbstractTableModel;

protected:
  // Call from the derived constructor, once rowCount() answers.
  void syncRows() { m_rows = rowCount(); }
  void refresh() {
    if (rowCount() != m_rows) {
      beginResetModel();
      m_rows = rowCount();
      endResetModel();
    } else if (m_rows > 0) {
      emit dataChanged(index(0, 0), index(m_rows - 1, columnCount() - 1));
    }
  }

private:
  int m_rows = 0; // rows the view knows of
};

} // namespace mlod
