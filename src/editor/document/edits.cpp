#include "editor/document/edits.h"

#include "core/jpc/joint_settings_edits.h"
#include "core/mapping/motion_mapping.h"
#include "core/project_mappings.h"
#include "editor/document/commands.h"
#include "editor/document/document.h"

#include <QCoreApplication>
#include <QFileInfo>

namespace mlod::edit {

namespace {
bool refuse(QString* out_error, const QString& reason) {
  if (out_error)
    *out_error = reason;
  return false;
}

QString tr(const char* text) {
  return QCoreApplication::translate("mlod::edit", text);
}

std::vector<std::string> jointNames(const Document& document, const std::vector<int>& joints) {
  const Asset* asset = document.currentAssetPtr();
  std::vector<std::string> names;
  for (int joint : joints)
    names.push_back(asset && joint >= 0 && joint < asset->skeleton.jointCount()
                        ? asset->skeleton.joints[std::size_t(joint)].name
                        : std::string());
  return names;
}

QString jointText(const Document& document, const std::vector<int>& joints) {
  return joints.size() == 1 ? QString::fromStdString(jointNames(document, joints)[0])
                            : tr("%1 joints").arg(joints.size());
}

const JointSettingsMap& currentJoints(const Document& document) {
  return document.project().assets[std::size_t(document.currentAsset())].joints;
}

void pushJointSettings(Document& document, const Result<JointSettingsMap>& after, const QString& text, int id = -1,
                       std::vector<int> mergeKey = {}) {
  if (!after) {
    emit document.message(tr("warning: %1").arg(QString::fromStdString(after.message())));
    return;
  }
  const JointSettingsMap& before = currentJoints(document);
  if (*after != before)
    document.undoStack()->push(
        new SetJointSettings(&document, document.currentAsset(), before, *after, text, id, std::move(mergeKey)));
}

bool pushMappings(Document& document, const Result<std::vector<ProjectMapping>>& after, const QString& text,
                  QString* out_error = nullptr) {
  if (!after)
    return refuse(out_error, QString::fromStdString(after.message()));
  if (*after == document.project().mappings)
    return false;
  document.undoStack()->push(new SetMappings(&document, document.project().mappings, *after, text));
  return true;
}

QString fileName(const Document& document, int asset) {
  return asset >= 0 && asset < document.assetCount() ? QFileInfo(document.assetFilePath(asset)).fileName() : QString();
}
} // namespace

void setAlpha(Document& document, double alpha) {
  if (alpha != document.project().alpha && !validateAlpha(alpha))
    document.undoStack()->push(new SetAlpha(&document, document.project().alpha, alpha));
}

void setMode(Document& document, JpcMode mode) {
  if (mode != document.project().mode)
    document.undoStack()->push(new SetMode(&document, document.project().mode, mode));
}

void addAsset(Document& document, std::shared_ptr<const Asset> asset, const QString& path, double unitScale) {
  ProjectAsset entry;
  entry.path = document.storedPath(path);
  entry.unitScale = unitScale;
  document.undoStack()->push(
      new ChangeAssets(&document, document.assetCount(), std::move(entry), std::move(asset), false));
}

void removeAsset(Document& document, int index) {
  if (index >= 0 && index < document.assetCount())
    document.undoStack()->push(
        new ChangeAssets(&document, index, document.project().assets[std::size_t(index)], document.asset(index), true));
}

void setJointAlpha(Document& document, const std::vector<int>& joints, std::optional<double> alpha) {
  if (!document.currentAssetPtr() || joints.empty())
    return;
  pushJointSettings(document, withJointAlpha(currentJoints(document), jointNames(document, joints), alpha),
                    tr("Set alpha of %1").arg(jointText(document, joints)), kCommandSetJointAlpha, joints);
}

void setJointThreshold(Document& document, const std::vector<int>& joints, int level, std::optional<double> threshold) {
  if (!document.currentAssetPtr() || joints.empty() || level >= document.levelCount())
    return;
  std::vector<int> key = joints;
  key.push_back(-1 - level);
  pushJointSettings(document,
                    withJointThreshold(currentJoints(document), jointNames(document, joints), level, threshold),
                    tr("Set threshold of %1 at level %2").arg(jointText(document, joints)).arg(level),
                    kCommandSetJointThreshold, std::move(key));
}

void setJointsLocked(Document& document, const std::vector<int>& joints, bool locked) {
  if (!document.currentAssetPtr() || joints.empty())
    return;
  const QString what = jointText(document, joints);
  pushJointSettings(document, withJointsLocked(currentJoints(document), jointNames(document, joints), locked),
                    locked ? tr("Lock %1").arg(what) : tr("Unlock %1").arg(what));
}

void setJointMeshImportance(Document& document, const std::vector<int>& joints, double importance) {
  if (!document.currentAssetPtr() || joints.empty())
    return;
  pushJointSettings(document,
                    withJointMeshImportance(currentJoints(document), jointNames(document, joints), importance),
                    tr("Set mesh importance of %1").arg(jointText(document, joints)), kCommandSetJointMeshImportance,
                    joints);
}

void applyToChildren(Document& document, int joint) {
  const Asset* asset = document.currentAssetPtr();
  if (!asset || joint < 0 || joint >= asset->skeleton.jointCount())
    return;
  pushJointSettings(document, withSettingsOnDescendants(currentJoints(document), asset->skeleton, joint),
                    tr("Apply %1's settings to its children").arg(jointText(document, {joint})));
}

bool applyLevelEdit(Document& document, const Result<LodSetEdit>& edit, const QString& text, QString* out_error, int id,
                    int level) {
  if (!edit)
    return refuse(out_error, QString::fromStdString(edit.message()));
  Project after = document.project();
  // the set in view: the asset's, or the one of the character the motion is viewed on
  applyLodSetEdit(after, document.currentAsset(), *edit, document.viewedCharacter());
  SetLevels::State before = SetLevels::stateOf(document.project()), state = SetLevels::stateOf(after);
  if (!(state == before))
    document.undoStack()->push(new SetLevels(&document, std::move(before), std::move(state), text, id, level));
  return true;
}

namespace {
QString levelName(const Document& document, int level) {
  const auto& levels = document.lods().levels;
  return level >= 0 && level < int(levels.size()) ? QString::fromStdString(levels[std::size_t(level)].name) : QString();
}
} // namespace

bool addLevel(Document& document, double threshold, QString* out_error) {
  const LodSet& lods = document.lods();
  return applyLevelEdit(document, addLodLevel(lods, threshold),
                        tr("Add level %1 (E = %2)").arg(QString::fromStdString(nextLodLevelName(lods))).arg(threshold),
                        out_error);
}

bool removeLevel(Document& document, int level, QString* out_error) {
  return applyLevelEdit(document, removeLodLevel(document.lods(), level),
                        tr("Remove level %1").arg(levelName(document, level)), out_error);
}

bool moveLevel(Document& document, int from, int to, QString* out_error) {
  return applyLevelEdit(document, moveLodLevel(document.lods(), from, to),
                        tr("Move level %1 to position %2").arg(levelName(document, from)).arg(to), out_error);
}

bool setLevelThreshold(Document& document, int level, double threshold, QString* out_error) {
  return applyLevelEdit(document, setLodLevelThreshold(document.lods(), level, threshold),
                        tr("Set level %1 threshold to %2").arg(level).arg(threshold), out_error,
                        kCommandSetLevelThreshold, level);
}

bool renameLevel(Document& document, int level, const QString& name, QString* out_error) {
  return applyLevelEdit(document, renameLodLevel(document.lods(), level, name.toStdString()),
                        tr("Rename level %1 to %2").arg(level).arg(name.trimmed()), out_error);
}

bool setLevelMeshRatio(Document& document, int level, double ratio, QString* out_error) {
  return applyLevelEdit(document, setLodLevelMeshRatio(document.lods(), level, ratio),
                        tr("Set level %1 mesh ratio to %2").arg(level).arg(ratio), out_error, kCommandSetLevelMeshRatio,
                        level);
}

bool setLevelSwitchDistance(Document& document, int level, double cm, QString* out_error) {
  return applyLevelEdit(document, setLodLevelSwitchDistance(document.lods(), level, cm),
                        tr("Set level %1 switch distance to %2 cm").arg(level).arg(cm), out_error,
                        kCommandSetLevelSwitchDistance, level);
}

bool assignMotion(Document& document, int motion, int character, QString* out_error, QString* out_warning) {
  const Result<std::vector<ProjectMapping>> after =
      withMotionAssigned(document.project(), document.importedAssets(), motion, character,
                         fileName(document, motion).toStdString(), fileName(document, character).toStdString());
  const QString text = after ? tr("Assign %1 to %2 (%3 joint pairs)")
                                   .arg(fileName(document, motion), fileName(document, character))
                                   .arg(after->back().mapping.pairs.size())
                             : QString();
  if (out_warning)
    out_warning->clear();
  if (!pushMappings(document, after, text, out_error))
    return false;
  const MappingCoverage coverage = mappingCoverage(after->back().mapping, document.asset(character)->skeleton);
  if (out_warning && drivesTooLittle(coverage))
    *out_warning =
        tr("%1 on %2: %3.")
            .arg(fileName(document, motion), fileName(document, character),
                 QString::fromStdString(tooLittleMappedReason(coverage, fileName(document, character).toStdString())));
  return true;
}

void unassignMotion(Document& document, int mapping) {
  pushMappings(document, withoutMapping(document.project(), mapping), tr("Unassign motion"));
}

bool setMappingPair(Document& document, int mapping, const QString& characterJoint, const QString& motionJoint) {
  const QString text =
      motionJoint.isEmpty() ? tr("Unmap %1").arg(characterJoint) : tr("Map %1 to %2").arg(motionJoint, characterJoint);
  return pushMappings(document,
                      withMappingPair(document.project(), document.importedAssets(), mapping,
                                      characterJoint.toStdString(), motionJoint.toStdString()),
                      text);
}

void resetMapping(Document& document, int mapping) {
  pushMappings(document, withAutomaticMapping(document.project(), document.importedAssets(), mapping),
               tr("Automatic joint mapping"));
}

} // namespace mlod::edit
