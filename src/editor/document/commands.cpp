#include "editor/document/commands.h"

#include "editor/document/document.h"

namespace mlod {

SetJointSettings::SetJointSettings(Document* document, int asset, Settings before, Settings after, const QString& text,
                                   int id, std::vector<int> mergeKey)
    : QUndoCommand(text), m_document(document), m_asset(asset), m_before(std::move(before)), m_after(std::move(after)),
      m_id(id), m_mergeKey(std::move(mergeKey)) {}

void SetJointSettings::undo() { m_document->applyJointSettings(m_asset, m_before); }
void SetJointSettings::redo() { m_document->applyJointSettings(m_asset, m_after); }

bool SetJointSettings::mergeWith(const QUndoCommand* other) {
  const auto* next = static_cast<const SetJointSettings*>(other);
  if (next->m_asset != m_asset || next->m_mergeKey != m_mergeKey)
    return false;
  m_after = next->m_after;
  setObsolete(m_after == m_before);
  return true;
}

namespace {
// Two states with the same number of levels in every set (a spin box's steps merge; an added
// or removed level does not).
bool sameLevelCounts(const SetLevels::State& a, const SetLevels::State& b) {
  if (a.lods.levels.size() != b.lods.levels.size() || a.own.size() != b.own.size())
    return false;
  for (std::size_t i = 0; i < a.own.size(); ++i)
    if (a.own[i].has_value() != b.own[i].has_value() ||
        (a.own[i] && a.own[i]->levels.size() != b.own[i]->levels.size()))
      return false;
  return true;
}
} // namespace

SetLevels::SetLevels(Document* document, State before, State after, const QString& text, int id, int level)
    : QUndoCommand(text), m_document(document), m_before(std::move(before)), m_after(std::move(after)), m_id(id),
      m_level(level) {}

SetLevels::State SetLevels::stateOf(const Project& project) {
  State state;
  state.lods = project.lods;
  for (const ProjectAsset& asset : project.assets) {
    state.own.push_back(asset.lods);
    state.joints.push_back(asset.joints);
  }
  return state;
}

void SetLevels::undo() {
  m_document->applyLevels(m_before.lods, m_before.own, m_before.joints);
}
void SetLevels::redo() {
  m_document->applyLevels(m_after.lods, m_after.own, m_after.joints);
}

bool SetLevels::mergeWith(const QUndoCommand* other) {
  const auto* next = static_cast<const SetLevels*>(other);
  if (next->m_level != m_level || !sameLevelCounts(next->m_after, m_after))
    return false;
  m_after = next->m_after;
  setObsolete(m_after == m_before);
  return true;
}

SetAlpha::SetAlpha(Document* document, double before, double after)
    : QUndoCommand(QObject::tr("Set alpha to %1 cm").arg(after)), m_document(document), m_before(before),
      m_after(after) {}

void SetAlpha::undo() { m_document->applyAlpha(m_before); }
void SetAlpha::redo() { m_document->applyAlpha(m_after); }

bool SetAlpha::mergeWith(const QUndoCommand* other) {
  m_after = static_cast<const SetAlpha*>(other)->m_after;
  setText(QObject::tr("Set alpha to %1 cm").arg(m_after));
  setObsolete(m_after == m_before);
  return true;
}

SetMode::SetMode(Document* document, JpcMode before, JpcMode after)
    : QUndoCommand(QObject::tr("Cluster %1").arg(after == JpcMode::Optimal ? QObject::tr("optimally") : QObject::tr("greedily"))),
      m_document(document), m_before(before), m_after(after) {}

void SetMode::undo() { m_document->applyMode(m_before); }
void SetMode::redo() { m_document->applyMode(m_after); }

ChangeAssets::ChangeAssets(Document* document, int index, ProjectAsset entry, std::shared_ptr<const Asset> asset,
                           bool remove)
    : QUndoCommand(remove ? QObject::tr("Remove %1").arg(QString::fromStdString(entry.path))
                          : QObject::tr("Import %1").arg(QString::fromStdString(entry.path))),
      m_document(document), m_index(index), m_entry(std::move(entry)), m_asset(std::move(asset)), m_remove(remove),
      m_mappings(document->project().mappings) {}

void ChangeAssets::add() {
  m_document->insertAsset(m_index, m_entry, m_asset);
  if (m_remove)
    m_document->applyMappings(m_mappings);
}
void ChangeAssets::erase() { m_document->eraseAsset(m_index); }
void ChangeAssets::undo() { m_remove ? add() : erase(); }
void ChangeAssets::redo() { m_remove ? erase() : add(); }

SetMappings::SetMappings(Document* document, std::vector<ProjectMapping> before, std::vector<ProjectMapping> after,
                         const QString& text)
    : QUndoCommand(text), m_document(document), m_before(std::move(before)), m_after(std::move(after)) {}

void SetMappings::undo() { m_document->applyMappings(m_before); }
void SetMappings::redo() { m_document->applyMappings(m_after); }

ReplaceAsset::ReplaceAsset(Document* document, int index, ProjectAsset beforeEntry, std::shared_ptr<const Asset> before,
                           ProjectAsset afterEntry, std::shared_ptr<const Asset> after, const QString& text)
    : QUndoCommand(text), m_document(document), m_index(index), m_beforeEntry(std::move(beforeEntry)),
      m_afterEntry(std::move(afterEntry)), m_before(std::move(before)), m_after(std::move(after)) {}

void ReplaceAsset::undo() { m_document->replaceAsset(m_index, m_beforeEntry, m_before); }
void ReplaceAsset::redo() { m_document->replaceAsset(m_index, m_afterEntry, m_after); }

} // namespace mlod
