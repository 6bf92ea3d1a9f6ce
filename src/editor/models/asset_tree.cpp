#include "editor/models/asset_tree.h"

#include <QFileInfo>

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

QModelIndex AssetTreeModel::addAsset(const std::shared_ptr<const Asset>& asset) {
  m_assets.push_back(asset);
  const QString file = QString::fromStdString(asset->sourcePath);
  const QString kind = asset->meshes.empty() ? tr("motion") : tr("character");
  // The height says at a glance whether the unit is right (a 1.8 cm character is not).
  const bool guessed = asset->unitSource == "guessed";
  const double height = standingHeightCm(*asset);
  QList<QStandardItem*> top =
      row(QFileInfo(file).fileName(),
          tr("%1 · %2 m tall · %3 cm/unit%4 · %5")
              .arg(kind)
              .arg(height / 100.0, 0, 'f', 2)
              .arg(asset->unitScale, 0, 'g', 5)
              .arg(guessed ? tr(" (guessed)") : QString())
              .arg(QString::fromStdString(asset->format)),
          tr("%1\nHeight: %2 cm\nUnit: %3 cm per file unit (%4)%5")
              .arg(file)
              .arg(height, 0, 'f', 1)
              .arg(asset->unitScale, 0, 'g', 6)
              .arg(QString::fromStdString(asset->unitSource))
              .arg(guessed ? tr("\nThe file states no unit: this one was guessed from the height. Edit → Asset Unit "
                                "changes it.")
                           : QString()));
  if (guessed)
    top.back()->setData(QColor(176, 112, 0), Qt::ForegroundRole);

  const Skeleton& skeleton = asset->skeleton;
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
  top.front()->appendRow(skeletonRow);

  QList<QStandardItem*> clipsRow = row(tr("Clips"), countText(qsizetype(asset->clips.size()), "clip", "clips"));
  for (const Clip& clip : asset->clips)
    clipsRow.front()->appendRow(row(QString::fromStdString(clip.name),
                                    tr("%1 frames · %2 fps · %3 s").arg(clip.frameCount).arg(clip.fps).arg(clip.durationSeconds(), 0, 'f', 2)));
  top.front()->appendRow(clipsRow);

  QList<QStandardItem*> meshesRow = row(tr("Meshes"), countText(qsizetype(asset->meshes.size()), "mesh", "meshes"));
  for (const SkinnedMesh& mesh : asset->meshes)
    meshesRow.front()->appendRow(row(QString::fromStdString(mesh.name),
                                     tr("%1 vertices · %2 triangles · %3 bones")
                                         .arg(mesh.vertexCount()).arg(mesh.triangleCount()).arg(mesh.boneCount())));
  top.front()->appendRow(meshesRow);
  appendRow(top);
  return indexFromItem(top.front());
}

void AssetTreeModel::setAssets(const std::vector<std::shared_ptr<const Asset>>& assets, const QStringList& paths,
                               const QStringList& notes) {
  removeRows(0, rowCount());
  m_assets.clear();
  for (std::size_t i = 0; i < assets.size(); ++i) {
    if (assets[i]) {
      const QModelIndex row = addAsset(assets[i]);
      const QString note = i < std::size_t(notes.size()) ? notes[qsizetype(i)] : QString();
      if (!note.isEmpty()) {
        QStandardItem* detail = item(row.row(), DetailColumn);
        detail->setText(note + " · " + detail->text());
        detail->setToolTip(note + "\n" + detail->toolTip());
      }
      continue;
    }
    const QString path = i < std::size_t(paths.size()) ? paths[qsizetype(i)] : QString();
    QList<QStandardItem*> missing = row(QFileInfo(path).fileName(), tr("missing: double-click to relink"),
                                        tr("%1 was not found or could not be imported.\nDouble-click to choose "
                                           "where the file is now.")
                                            .arg(path));
    missing.front()->setForeground(QColor(200, 40, 40));
    missing.back()->setForeground(QColor(200, 40, 40));
    appendRow(missing);
    m_assets.push_back(nullptr);
  }
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
