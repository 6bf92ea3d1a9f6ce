#pragma once
// The edits a user makes to the open project (docs/architecture.md section 7). Each checks its
// input with core's rules (core/lod/lod_levels.h, core/jpc/joint_settings_edits.h,
// core/project_mappings.h, validateAlpha()) and pushes one small command (commands.h) on the
// document's undo stack, or refuses and pushes nothing (the functions that return bool give
// the reason). An edit that changes nothing pushes nothing; a slider drag merges into one step.
// The document holds the state; these are the only way its figures change.

#include "core/asset.h"
#include "core/jpc/jpc_settings.h"
#include "core/lod/lod_levels.h"

#include <QString>
#include <memory>
#include <optional>
#include <vector>

namespace mlod {

class Document;

namespace edit {

// The project's settings. alpha in cm (refused unless validateAlpha() accepts it).
void setAlpha(Document& document, double alpha);
void setMode(Document& document, JpcMode mode);

// Assets: `path` is the file as imported, `unitScale` cm per file unit (0: the file's own).
void addAsset(Document& document, std::shared_ptr<const Asset> asset, const QString& path, double unitScale);
void removeAsset(Document& document, int index);

// Per-joint settings of the asset in view; `joints` are skeleton indices of it.
void setJointAlpha(Document& document, const std::vector<int>& joints, std::optional<double> alpha);
void setJointThreshold(Document& document, const std::vector<int>& joints, int level, std::optional<double> threshold);
void setJointsLocked(Document& document, const std::vector<int>& joints, bool locked);
// Mesh importance (finite, > 0; 1 = as any other joint): scales the mesh LOD's cost of
// removing the vertices the joints influence (core/mesh/mesh_lod.h).
void setJointMeshImportance(Document& document, const std::vector<int>& joints, double importance);
void applyToChildren(Document& document, int joint); // the joint's settings to every descendant

// LOD levels (thresholds in cm·degrees, distances in cm).
bool addLevel(Document& document, double threshold, QString* out_error = nullptr);
bool removeLevel(Document& document, int level, QString* out_error = nullptr);
bool moveLevel(Document& document, int from, int to, QString* out_error = nullptr);
bool setLevelThreshold(Document& document, int level, double threshold, QString* out_error = nullptr);
bool renameLevel(Document& document, int level, const QString& name, QString* out_error = nullptr);
bool setLevelMeshRatio(Document& document, int level, double ratio, QString* out_error = nullptr);
bool setLevelSwitchDistance(Document& document, int level, double cm, QString* out_error = nullptr);
// Any accepted level edit (a generated set: replaceLodLevels()) as one undo step named `text`;
// `id` and `level` let a spin box's steps merge.
bool applyLevelEdit(Document& document, const Result<LodSetEdit>& edit, const QString& text,
                    QString* out_error = nullptr, int id = -1, int level = -1);

// Motion mappings: motion asset `motion` played on character asset `character` with the
// automatic joint table; a table's pair (`motionJoint` empty: the character joint at rest);
// the automatic table again. setMappingPair() returns false when nothing changes too.
// assignMotion() sets *out_warning (when given; else clears it) where the automatic table
// drives too little of the character (core's drivesTooLittle(), the rule `motionlod export
// --motion` refuses by): a motion of another rig, most of the body at rest.
bool assignMotion(Document& document, int motion, int character, QString* out_error = nullptr,
                  QString* out_warning = nullptr);
void unassignMotion(Document& document, int mapping);
bool setMappingPair(Document& document, int mapping, const QString& characterJoint, const QString& motionJoint);
void resetMapping(Document& document, int mapping);

} // namespace edit
} // namespace mlod
