#pragma once
// The Assets dock's model: one row per imported file, with its skeleton (as a joint
// tree), clips and meshes below it. The rows below an asset are made when it is first
// expanded (fetchMore()): a project may list thousands of assets, and their joints were
// hundreds of thousands of items nobody looks at (issue 29).

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

  // Shows one row per asset, in order; a null asset is a missing file at `paths[i]` (its row
  // says so and how to relink it). `notes[i]`, where given, is added to row i's details (what
  // the asset drives or is driven by). Rows whose asset, path and note are as shown are kept,
  // so a call after each of many imports costs a comparison per row, not a rebuild.
  void setAssets(const std::vector<std::shared_ptr<const Asset>>& assets, const QStringList& paths,
                 const QStringList& notes = {});
  // Shows `asset` (null: missing) at an existing row, keeping the row's note.
  void setAsset(int row, const std::shared_ptr<const Asset>& asset, const QString& path);
  bool isMissing(int row) const { return row >= 0 && row < assetCount() && !m_assets[std::size_t(row)]; }
  const Asset* assetAt(int row) const;
  int assetCount() const { return static_cast<int>(m_assets.size()); }
  // Where an index of this model lies: the asset row it belongs to (at any depth; -1 for an
  // invalid index), and the clip it names (a row under the asset's "Clips", else -1).
  int assetRow(const QModelIndex& index) const;
  int clipRow(const QModelIndex& index) const;

  // The rows below an asset, in this order.
  enum GroupRow { SkeletonGroup, ClipsGroup, MeshesGroup };

  // An asset row not expanded yet has children to fetch.
  bool hasChildren(const QModelIndex& parent = {}) const override;
  bool canFetchMore(const QModelIndex& parent) const override;
  void fetchMore(const QModelIndex& parent) override;

private:
  // What an asset's row says (its file, kind, height and unit), the rows below it (its
  // skeleton as a joint tree, clips and meshes), what the row of a missing file says.
  static void describeAsset(QStandardItem* name, QStandardItem* detail, const Asset* asset);
  static void addDetails(QStandardItem* top, const Asset& asset);
  static void describeMissing(QStandardItem* name, QStandardItem* detail, const QString& path);
  // The asset row `parent` is, with its rows still to make; -1 otherwise.
  int rowToFetch(const QModelIndex& parent) const;
  void showRow(int row, const std::shared_ptr<const Asset>& asset, const QString& path, const QString& note);

  // What each row shows.
  std::vector<std::shared_ptr<const Asset>> m_assets;
  QStringList m_paths;
  QStringList m_notes;
  std::vector<bool> m_fetched; // the rows below the asset are made
};

} // namespace mlod
