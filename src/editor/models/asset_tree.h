#pragma once
// The Assets dock's model: one row per imported file, with its skeleton (as a joint
// tree), clips and meshes below it.

#include "core/asset.h"

#include <QStandardItemModel>

#include <memory>

namespace mlod {

// "1 joint", "38 joints": English plurals for counts shown in the UI.
QString countText(qsizetype count, const char* singular, const char* plural);

class AssetTreeModel : public QStandardItemModel {
  Q_OBJECT
public:
  enum Column { NameColumn, DetailColumn, ColumnCount };
  explicit AssetTreeModel(QObject* parent = nullptr);

  // Adds a row for the asset and returns its index.
  QModelIndex addAsset(const std::shared_ptr<const Asset>& asset);
  // Replaces every row: one per asset, in order; a null asset is a missing file at `paths[i]`
  // (its row says so and how to relink it).
  // `notes[i]`, where given, is added to row i's details (what the asset drives or is driven by).
  void setAssets(const std::vector<std::shared_ptr<const Asset>>& assets, const QStringList& paths,
                 const QStringList& notes = {});
  bool isMissing(int row) const { return row >= 0 && row < assetCount() && !m_assets[std::size_t(row)]; }
  const Asset* assetAt(int row) const;
  int assetCount() const { return static_cast<int>(m_assets.size()); }
  // Where an index of this model lies: the asset row it belongs to (at any depth; -1 for an
  // invalid index), and the clip it names (a row under the asset's "Clips", else -1).
  int assetRow(const QModelIndex& index) const;
  int clipRow(const QModelIndex& index) const;

  // The rows below an asset, in this order.
  enum GroupRow { SkeletonGroup, ClipsGroup, MeshesGroup };

private:
  std::vector<std::shared_ptr<const Asset>> m_assets;
};

} // namespace mlod
