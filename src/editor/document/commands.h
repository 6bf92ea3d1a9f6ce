#pragma once
// Every edit of the document is one of these small commands (Tiled's model). Ids sit in one
// enum so a slider drag merges into one undo step. Commands hold the Document and values,
// never pointers into views.

#include "core/project.h"

#include <QUndoCommand>

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace mlod {

class Asset;
class Document;

enum CommandId {
  kCommandSetAlpha = 1,
  kCommandSetJointAlpha,
  kCommandSetJointThreshold,
  kCommandSetLevelThreshold,
  kCommandSetLevelMeshRatio,
  kCommandSetLevelSwitchDistance,
  kCommandSetJointMeshImportance,
};

// Replaces one asset's per-joint settings (threshold, alpha, lock, apply to children).
// Merges with the previous command of the same id, asset, joints and `mergeKey`.
class SetJointSettings : public QUndoCommand {
public:
  using Settings = std::map<std::string, JointSettings>;
  SetJointSettings(Document* document, int asset, Settings before, Settings after, const QString& text, int id = -1,
                   std::vector<int> mergeKey = {});
  void undo() override;
  void redo() override;
  int id() const override { return m_id; }
  bool mergeWith(const QUndoCommand* other) override;

private:
  Document* m_document;
  int m_asset;
  Settings m_before, m_after;
  int m_id;
  std::vector<int> m_mergeKey;
};

// The level lists (the project's and each asset's own: core/project.h's lodSetFor()) and,
// with them, every asset's per-joint overrides (which follow their level).
class SetLevels : public QUndoCommand {
public:
  struct State {
    LodSet lods;                                              // the project's LOD set
    std::vector<std::optional<LodSet>> own;                   // per asset: its own set, if any
    std::vector<std::map<std::string, JointSettings>> joints; // per asset
    friend bool operator==(const State&, const State&) = default;
  };
  static State stateOf(const Project& project); // its LOD sets and every asset's joint settings
  // Merges with the previous command of the same id and `level` (a spin box's steps).
  SetLevels(Document* document, State before, State after, const QString& text, int id = -1, int level = -1);
  void undo() override;
  void redo() override;
  int id() const override { return m_id; }
  bool mergeWith(const QUndoCommand* other) override;

private:
  Document* m_document;
  State m_before, m_after;
  int m_id;
  int m_level;
};

class SetAlpha : public QUndoCommand {
public:
  SetAlpha(Document* document, double before, double after);
  void undo() override;
  void redo() override;
  int id() const override { return kCommandSetAlpha; }
  bool mergeWith(const QUndoCommand* other) override;

private:
  Document* m_document;
  double m_before, m_after;
};

// Greedy (the paper's) or optimal clustering, for the whole project.
class SetMode : public QUndoCommand {
public:
  SetMode(Document* document, JpcMode before, JpcMode after);
  void undo() override;
  void redo() override;

private:
  Document* m_document;
  JpcMode m_before, m_after;
};

// Adds (or, with `remove`, removes) one asset at `index`.
class ChangeAssets : public QUndoCommand {
public:
  ChangeAssets(Document* document, int index, ProjectAsset entry, std::shared_ptr<const Asset> asset, bool remove);
  void undo() override;
  void redo() override;

private:
  void add();
  void erase();
  Document* m_document;
  int m_index;
  ProjectAsset m_entry;
  std::shared_ptr<const Asset> m_asset;
  bool m_remove;
  std::vector<ProjectMapping> m_mappings; // before the command: a removed asset's mappings come back on undo
};

// Replaces the project's motion-to-character mappings (assign, unassign, edit a table).
class SetMappings : public QUndoCommand {
public:
  SetMappings(Document* document, std::vector<ProjectMapping> before, std::vector<ProjectMapping> after,
              const QString& text);
  void undo() override;
  void redo() override;

private:
  Document* m_document;
  std::vector<ProjectMapping> m_before, m_after;
};

// Replaces one asset by the same file imported again (a new unit scale).
class ReplaceAsset : public QUndoCommand {
public:
  ReplaceAsset(Document* document, int index, ProjectAsset beforeEntry, std::shared_ptr<const Asset> before,
               ProjectAsset afterEntry, std::shared_ptr<const Asset> after, const QString& text);
  void undo() override;
  void redo() override;

private:
  Document* m_document;
  int m_index;
  ProjectAsset m_beforeEntry, m_afterEntry;
  std::shared_ptr<const Asset> m_before, m_after;
};

} // namespace mlod
