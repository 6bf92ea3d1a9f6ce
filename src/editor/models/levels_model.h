#pragma once
// The LOD levels dock's model: one row per level with its motion threshold (editable) and
// the clip's simplified % there. Until the core LodSet lands, a level is its threshold.

#include <QAbstractTableModel>

namespace mlod {

class Document;

class LevelsModel : public QAbstractTableModel {
  Q_OBJECT
public:
  enum Column { NameColumn, ThresholdColumn, SimplifiedColumn, ColumnCount };
  explicit LevelsModel(Document* document, QObject* parent = nullptr);

  int rowCount(const QModelIndex& parent = {}) const override;
  int columnCount(const QModelIndex& parent = {}) const override;
  QVariant data(const QModelIndex& index, int role = Qt::DisplayRole) const override;
  bool setData(const QModelIndex& index, const QVariant& value, int role = Qt::EditRole) override;
  Qt::ItemFlags flags(const QModelIndex& index) const override;
  QVariant headerData(int section, Qt::Orientation orientation, int role = Qt::DisplayRole) const override;

private:
  Document* m_document;
};

} // namespace mlod
