#include "editor/models/asset_tree.h"

#include <QFileInfo>
#include <cassert>

namespace mlod {

QString countText(qsizetype count, const char* singular, const char* plural) {
  return QString("%1 %2").arg(count).arg(QString::fromUtf8(count == 1 ? singular : plural));
}

namespace {
QList<QStandardItem*> row(const QString& name, const QString& detail, const QString& tooltip = {}) {
  auto* nameItem = new QStandardItem(name);
  auto* detailItem = new QStandardItem(detail);
  nameItem->setEditable(false);
  detailItem->setEditable(false);
  if (!tooltip.isEmpty()) {
    nameItem->setToolTip(tooltip);
    detailItem->setToolTip(tooltip);
  }
  return {nameItem, detailItem};
}
} // namespace

AssetTreeModel::AssetTreeModel(QObject* parent) : QStandardItemModel(0, ColumnCount, parent) {
  setHorizontalHeaderLabels({tr("Name"), tr("Details")});
}

void AssetTreeModel::describeAsset(QStandardItem* name, QStandardItem* detail, const Asset* asset) {
  const QString file = QString::fromStdString(asset->sourcePath);
  const QString kind = asset->meshes.empty() ? tr("motion") : tr("character");
  // The height says at a glance whether the unit is right (a 1.8 cm character is not).
  const bool guessed = asset->unitSource == "guessed";
  const double height = standingHeightCm(*asset);
  const QString tooltip =
      tr("%1\nHeight: %2 cm\nUnit: %3 cm per file unit (%4)%5")
          .arg(file)
          .arg(height, 0, 'f', 1)
          .arg(asset->unitScale, 0, 'g', 6)
          .arg(QString::fromStdString(asset->unitSource))
          .arg(guessed ? tr("\nThe file states no unit: this one was guessed from the height. Edit → Asset Unit "
                            "changes it.")
                       : QString());
  name->setText(QFileInfo(file).fileName());
  name->setToolTip(tooltip);
  detail->setText(tr("%1 · %2 m tall · %3 cm/unit%4 · %5")
                      .arg(kind)
                      .arg(height / 100.0, 0, 'f', 2)
                      .arg(asset->unitScale, 0, 'g', 5)
                      .arg(guessed ? tr(" (guessed)") : QString())
                      .arg(QString::fromStdString(asset->format)));
  detail->setToolTip(tooltip);
  if (guessed)
    detail->setData(QColor(176, 112, 0), Qt::ForegroundRole);
}

void AssetTreeModel::addDetails(QStandardItem* top, const Asset& asset) {
  const Skeleton& skeleton = asset.skeleton;
  QList<QStandardItem*> skeletonRow =
      row(tr("Skeleton"), countText(skeleton.jointCount(), "joint", "joints"), tr("Joints in parent-before-child order"));
  std::vector<QStandardItem*> jointItems;
  for (const Joint& joint : skeleton.joints) {
    const glm::vec3& offset = joint.rest.translation;
    QList<QStandardItem*> jointRow =
        row(QString::fromStdString(joint.name), tr("offset %1 cm").arg(double(glm::length(offset)), 0, 'f', 2),
            tr("Rest offset from the parent: (%1, %2, %3) cm")
                .arg(double(offset.x), 0, 'f', 3).arg(double(offset.y), 0, 'f', 3).arg(double(offset.z), 0, 'f', 3));
    QStandardItem* parent = joint.parent < 0 ? skeletonRow.front() : jointItems[std::size_t(joint.parent)];
    jointItems.push_back(jointRow.front());
    parent->appendRow(jointRow);
  }
  top->appendRow(skeletonRow);

  QList<QStandardItem*> clipsRow = row(tr("Clips"), countText(qsizetype(asset.clips.size()), "clip", "clips"));
  for (const Clip& clip : asset.clips)
    clipsRow.front()->appendRow(row(QString::fromStdString(clip.name),
                                    tr("%1 frames · %2 fps · %3 s").arg(clip.frameCount).arg(clip.fps).arg(clip.durationSeconds(), 0, 'f', 2)));
  top->appendRow(clipsRow);

  QList<QStandardItem*> meshesRow = row(tr("Meshes"), countText(qsizetype(asset.meshes.size()), "mesh", "meshes"));
  for (const SkinnedMesh& mesh : asset.meshes)
    meshesRow.front()->appendRow(row(QString::fromStdString(mesh.name),
                                     tr("%1 vertices · %2 triangles · %3 bones")
                                         .arg(mesh.vertexCount()).arg(mesh.triangleCount()).arg(mesh.boneCount())));
  top->appendRow(meshesRow);
}

void AssetTreeModel::describeMissing(QStandardItem* name, QStandardItem* detail, const QString& path) {
  const QString tooltip =
      tr("%1 was not found or could not be imported.\nDouble-click to choose where the file is now.").arg(path);
  name->setText(QFileInfo(path).fileName());
  detail->setText(tr("missing: double-click to relink"));
  for (QStandardItem* item : {name, detail}) {
    item->setToolTip(tooltip);
    item->setForeground(QColor(200, 40, 40));
  }
}

// A row's two items are kept and filled again: replacing them would shift every later row of
// the model, once per imported asset.
void AssetTreeModel::showRow(int rowIndex, const std::shared_ptr<const Asset>& asset, const QString& path,
                             const QString& note) {
  const std::size_t at = std::size_t(rowIndex);
  if (rowIndex >= assetCount()) {
    appendRow(row(QString(), QString()));
    m_assets.emplace_back();
    m_paths << QString();
    m_notes << QString();
    m_fetched.push_back(false);
  }
  QStandardItem* name = item(rowIndex, NameColumn);
  QStandardItem* detail = item(rowIndex, DetailColumn);
  if (m_fetched[at])
    removeRows(0, name->rowCount(), name->index());
  m_assets[at] = asset;
  m_paths[rowIndex] = path;
  m_notes[rowIndex] = note;
  m_fetched[at] = false;
  for (QStandardItem* item : {name, detail})
    item->setData(QVariant(), Qt::ForegroundRole);
  if (!asset) {
    describeMissing(name, detail, path);
    return;
  }
  describeAsset(name, detail, asset.get());
  if (!note.isEmpty()) {
    detail->setText(note + " · " + detail->text());
    detail->setToolTip(note + "\n" + detail->toolTip());
  }
}

int AssetTreeModel::rowToFetch(const QModelIndex& parent) const {
  const bool assetRow = parent.isValid() && !parent.parent().isValid() && parent.row() < assetCount();
  return assetRow && m_assets[std::size_t(parent.row())] && !m_fetched[std::size_t(parent.row())] ? parent.row() : -1;
}

bool AssetTreeModel::hasChildren(const QModelIndex& parent) const {
  return rowToFetch(parent) >= 0 || QStandardItemModel::hasChildren(parent);
}

bool AssetTreeModel::canFetchMore(const QModelIndex& parent) const {
  return rowToFetch(parent) >= 0;
}

void AssetTreeModel::fetchMore(const QModelIndex& parent) {
  const int rowIndex = rowToFetch(parent);
  if (rowIndex < 0)
    return;
  m_fetched[std::size_t(rowIndex)] = true;
  addDetails(item(rowIndex, NameColumn), *m_assets[std::size_t(rowIndex)]);
}

void AssetTreeModel::setAssets(const std::vector<std::shared_ptr<const Asset>>& assets, const QStringList& paths,
                               const QStringList& notes) {
  if (assets.size() != m_assets.size()) { // assets added or removed: rows moved
    removeRows(0, rowCount());
    m_assets.clear();
    m_paths.clear();
    m_notes.clear();
    m_fetched.clear();
  }
  for (std::size_t i = 0; i < assets.size(); ++i) {
    const int at = static_cast<int>(i);
    const QString path = at < paths.size() ? paths[at] : QString();
    const QString note = at < notes.size() ? notes[at] : QString();
    if (at < assetCount() && m_assets[i] == assets[i] && m_paths[at] == path && m_notes[at] == note)
      continue;
    showRow(at, assets[i], path, note);
  }
}

void AssetTreeModel::setAsset(int rowIndex, const std::shared_ptr<const Asset>& asset, const QString& path) {
  assert(rowIndex >= 0 && rowIndex < assetCount());
  showRow(rowIndex, asset, path, m_notes[rowIndex]);
}

int AssetTreeModel::assetRow(const QModelIndex& index) const {
  if (!index.isValid())
    return -1;
  QModelIndex top = index;
  while (top.parent().isValid())
    top = top.parent();
  return top.row();
}

int AssetTreeModel::clipRow(const QModelIndex& index) const {
  const QModelIndex group = index.parent();
  const bool underClips =
      group.isValid() && group.parent().isValid() && !group.parent().parent().isValid() && group.row() == ClipsGroup;
  return underClips ? index.row() : -1;
}

const Asset* AssetTreeModel::assetAt(int rowIndex) const {
  if (rowIndex < 0 || rowIndex >= assetCount())
    return nullptr;
  return m_assets[std::size_t(rowIndex)].get();
}

} // namespace mlod
