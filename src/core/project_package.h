#pragma once
// A project's LOD package (docs/architecture.md sections 3 and 8): the asset's LodSet (lodSetFor()) and
// JPC settings applied to one of its assets, with every motion assigned to that asset through
// the project's mappings played on it as extra clips (retargeted, mapping/motion_mapping.h).
// This sits above both project.h and lod/lod_package.h, so the package data (what exporters
// see) never depends on the project model.
//
// `imported[i]` is the project's asset i as imported, null where it could not be (an error
// only when the package needs it).

#include "core/asset.h"
#include "core/clip.h"
#include "core/error.h"
#include "core/lod/lod_package.h"
#include "core/project.h"

#include <atomic>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace mlod {

// The clips of every motion the project assigns to its asset `character`, retargeted onto
// that asset's skeleton through their mappings, in mapping order. Errors: a bad asset index,
// an assigned motion that was not imported, a mapping that does not fit the skeletons.
Result<std::vector<Clip>> assignedClips(const Project& project, std::span<const Asset* const> imported, int character);

// A project's package of its asset `asset`: its LodSet (lodSetFor()), its JPC settings for the
// asset, and assignedClips(). Errors: a project that does not validate, a bad asset index,
// assets not imported, and those of buildLodPackage() and assignedClips(). `cancel` as for
// buildLodPackage() (core/cancel.h, may be null).
Result<LodPackage> buildLodPackage(const Project& project, std::span<const Asset* const> imported, int asset,
                                   std::span<const int> levels = {}, const LodPackageProgress& progress = {},
                                   const std::atomic<bool>* cancel = nullptr);

// The plan of a package of `asset` alone with `levelCount` levels (`levels`: the ones
// exported, empty = all): its joints, the frames of its clips.
LodPackagePlan packagePlan(const Asset& asset, int levelCount, std::span<const int> levels = {});

// The plan of buildLodPackage(project, imported, asset, levels): the asset's joints, the
// frames of its clips and of every motion assigned to it (those imported), the levels.
LodPackagePlan packagePlan(const Project& project, std::span<const Asset* const> imported, int asset,
                           std::span<const int> levels = {});

// The asset of a project a package is made of when none is named: the first asset that
// plays a clip or carries a skinned mesh and is the character of a mapping, else the first
// asset with a skinned mesh, else the first asset. -1 for a project without assets.
int defaultPackageAsset(const Project& project, std::span<const Asset* const> imported);

// The character a project exports for its asset `asset` (the asset in view): the one whose LOD
// set it plays with, lodSetOwner(project, asset, viewedCharacter): a motion's viewed character
// when it is mapped onto it, else its first mapping's; any other asset itself. The one rule
// behind the studio's Export dialog and `motionlod export` of a project (issue 26: each had
// its own). For no asset in range, defaultPackageAsset(project, imported); -1 there when
// `imported` is empty (import the candidates, the mappings' characters or else every asset,
// and ask again) or the project has no asset.
int exportCharacterOf(const Project& project, int asset, int viewedCharacter = -1,
                      std::span<const Asset* const> imported = {});

// The assets a project can export as characters (`motionlod export --character`): every asset
// that is no motion mapped onto a character (a mapped motion is exported with the character
// it plays on), in project order.
std::vector<int> exportCharacters(const Project& project);
// The character of exportCharacters() that `name` names: its index ("2"), its stored path, its
// file name ("BCN_Epileptic.X") or its file name without the extension ("BCN_Epileptic").
// Errors name what is wrong and list the project's characters ("0 BCN_Epileptic.X, 2
// Testwuson.X"): no such character, a name that fits several, an index out of range, a
// motion mapped onto a character (its character is named).
Result<int> exportCharacterNamed(const Project& project, std::string_view name);
// "0 BCN_Epileptic.X, 2 Testwuson.X": exportCharacters() by index and file name.
std::string exportCharacterList(const Project& project);

} // namespace mlod
