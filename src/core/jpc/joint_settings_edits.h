#pragma once
// Edits of one asset's per-joint JPC settings as an author makes them (the Skeleton dock,
// docs/architecture.md sections 3 and 7): each returns the settings after the edit, tidied, and
// never changes its input. Tidy: an entry that says nothing (no alpha, no override, not
// locked, mesh importance 1) is dropped, and trailing absent overrides with it, so equal settings compare equal
// and projects stay small.
//
// Units: alpha in cm, thresholds in cm·degrees.

#include "core/error.h"
#include "core/jpc/jpc_settings.h"
#include "core/skeleton.h"

#include <map>
#include <optional>
#include <span>
#include <string>

namespace mlod {

using JointSettingsMap = std::map<std::string, JointSettings>; // by joint name

void tidyJointSettings(JointSettingsMap& joints);

// `alpha` for every joint of `names` (absent: the project's). Errors: an alpha that does not
// validate (validateAlpha()).
Result<JointSettingsMap> withJointAlpha(const JointSettingsMap& joints, std::span<const std::string> names,
                                        std::optional<double> alpha);
// The override of every joint of `names` at LOD level `level` (absent: the level's own).
// Errors: level 0 (the original has nothing to override) or below, a threshold that does
// not validate.
Result<JointSettingsMap> withJointThreshold(const JointSettingsMap& joints, std::span<const std::string> names,
                                            int level, std::optional<double> threshold);
// The mesh importance of every joint of `names` (1: as any other joint; core/mesh/mesh_lod.h).
// Errors: an importance that does not validate (validateMeshImportance()).
Result<JointSettingsMap> withJointMeshImportance(const JointSettingsMap& joints, std::span<const std::string> names,
                                                 double importance);
JointSettingsMap withJointsLocked(const JointSettingsMap& joints, std::span<const std::string> names, bool locked);
// Joint `joint`'s settings (of `skeleton`) copied to every one of its descendants.
JointSettingsMap withSettingsOnDescendants(const JointSettingsMap& joints, const Skeleton& skeleton, int joint);

} // namespace mlod
