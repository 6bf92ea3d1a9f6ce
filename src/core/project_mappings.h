#pragma once
// Edits of a project's motion-to-character mappings (docs/architecture.md sections 3 and 7),
// as the editor makes them: each returns the project's mapping list after the edit, or the
// reason it is refused, and never changes its input. `imported[i]` is the project's asset i
// as imported (null where the file is missing).

#include "core/asset.h"
#include "core/error.h"
#include "core/project.h"

#include <span>
#include <string>
#include <vector>

namespace mlod {

// Motion asset `motion` assigned to character asset `character` with the automatic joint
// mapping (MotionMapping::automatic), named `motionName` and `characterName` for people;
// it replaces an earlier assignment of that motion to that character and goes last. Errors:
// the same asset twice or one out of range, an asset not imported, a motion without a clip,
// no joint that matches.
Result<std::vector<ProjectMapping>> withMotionAssigned(const Project& project, std::span<const Asset* const> imported,
                                                       int motion, int character, const std::string& motionName,
                                                       const std::string& characterName);
// Errors: no such mapping.
Result<std::vector<ProjectMapping>> withoutMapping(const Project& project, int mapping);
// Mapping `mapping`'s table with `motionJoint` driving `characterJoint` (MotionMapping::set;
// a pair that held either goes), or, for an empty `motionJoint`, the character joint left at
// its rest pose. Errors: no such mapping, an asset not imported, a joint its skeleton lacks.
Result<std::vector<ProjectMapping>> withMappingPair(const Project& project, std::span<const Asset* const> imported,
                                                    int mapping, const std::string& characterJoint,
                                                    const std::string& motionJoint);
// Mapping `mapping`'s table back to the automatic one (its names kept). Errors: no such
// mapping, an asset not imported.
Result<std::vector<ProjectMapping>> withAutomaticMapping(const Project& project, std::span<const Asset* const> imported,
                                                         int mapping);

} // namespace mlod
