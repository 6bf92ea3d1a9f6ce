#pragma once
// The project document (docs/architecture.md section 3): which assets, how their joints are tuned, and
// the LOD levels, saved as versioned JSON (.mlod). No Qt: the editor and the CLI both read
// it, so `motionlod simplify PROJECT.mlod` reproduces the editor's figures.
//
// Units: thresholds in cm·degrees, alpha in cm, unit scale in cm per file unit.
//
// LOD levels: a core LodSet (lod/lod_set.h). Level 0 is the original (threshold 0, nothing
// clustered); level i >= 1 clusters at its motion threshold. Per-joint threshold overrides
// are indexed by LodSet level, so index 0 is never set.

#include "core/error.h"
#include "core/jpc/jpc_settings.h"
#include "core/lod/lod_levels.h"
#include "core/lod/lod_set.h"
#include "core/mapping/motion_mapping.h"

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mlod {

// Version 4: as version 3, and an asset may carry its own LOD set, "lods" (the same object as
// the project's): a character's levels, switch distances and mesh ratios are its own
// (docs/architecture.md section 3). An asset without one plays with the project's "lods"; a
// motion mapped onto a character plays with the character's (lodSetOwner()). A "lods"
// object may say where the character is skinned, "skinning": "gpu" | "cpu" (LodSet::skinning;
// written always, absent in files saved before it was kept: "gpu").
// Version 3 (read, never written): {"format":"motionlod-project","version":3,"alpha","mode",
//             "lods":{"projection":{"vertical_fov_degrees","viewport_height_pixels"},"bounding_radius_cm",
//                     "levels":[{"name","threshold","mesh_ratio","switch_distance_cm","pixel_error",
//                                "screen_size_pixels","motion_error_cm","mesh_error_cm","triangles","active_joints"}]},
//             "assets":[{"path","unit_scale" (> 0; absent: the file's own unit),
//                        "joints":{NAME:{"alpha","thresholds":[E|null],"locked"}}}],
//             "mappings":[{"motion","character","table":<motion_mapping.h's JSON>}],  (optional)
//             "current":{"asset","clip","level","joint"}}
// A version 3 project's one set is every asset's (none has its own).
// Version 2 (read, never written): as version 3, with "unit_scale" always present and 0 for
// the file's own unit.
// Version 1 (read, never written): "levels":[{"threshold"}] with no original level: level i
// of version 1 becomes LodSet level i + 1 ("LOD<i+1>", mesh ratio 1, distance 0), and with it
// the per-joint overrides and the current level.
inline constexpr int kProjectVersion = 4;
// Caps checked when a project is read, before anything is built from it: a file of 70,000
// levels would otherwise run for minutes (every level is clustered on every export).
inline constexpr int kMaxProjectLevels = 32;                      // level 0 included
inline constexpr std::uint64_t kMaxProjectFileBytes = 64u << 20; // 64 MiB
// Names and paths are refused past these lengths (bytes) with the field named, never clipped:
// a clipped joint name would silently tune another joint, a clipped path name another file.
// Level names: kMaxLevelNameBytes (lod/lod_set.h).
inline constexpr std::size_t kMaxJointNameBytes = 1024;
inline constexpr std::size_t kMaxAssetPathBytes = 4096; // Linux's PATH_MAX
inline constexpr const char* kProjectFormat = "motionlod-project";

struct ProjectAsset {
  // Where the file is: relative to the project file's folder when saved ('/' separators),
  // absolute or relative to the working directory in memory until then.
  std::string path;
  double unitScale = 0.0;                      // cm per file unit; 0 = the file's own (ImportOptions)
  std::map<std::string, JointSettings> joints; // per-joint tuning by joint name
  // Its own LOD set (a character's levels, distances and mesh ratios; the per-joint
  // threshold overrides in `joints` are per level of it); absent: it plays with
  // Project::lods. Read it through lodSetFor().
  std::optional<LodSet> lods = std::nullopt;
  friend bool operator==(const ProjectAsset&, const ProjectAsset&) = default;
};

// A motion asset assigned to a character asset through a joint mapping (indices into
// Project::assets).
struct ProjectMapping {
  int motion = -1;
  int character = -1;
  MotionMapping mapping;
  friend bool operator==(const ProjectMapping&, const ProjectMapping&) = default;
};

// What the editor had in view (restored on open; not part of any figure).
struct ProjectView {
  int asset = -1;
  int clip = 0;
  int level = 1; // a new project shows its first simplified level (clamped to the levels there are)
  std::string joint;
  friend bool operator==(const ProjectView&, const ProjectView&) = default;
};

// The levels of a new project: the original and the paper's Table 1 thresholds 5, 50, 100,
// 300 cm·degrees, full meshes, switch distances unset (0) until edited or generated.
LodSet defaultLodSet();

struct Project {
  std::vector<ProjectAsset> assets;
  double alpha = kDefaultJpcAlpha; // cm, every joint without its own
  JpcMode mode = JpcMode::Greedy;
  LodSet lods = defaultLodSet(); // level 0 the original
  std::vector<ProjectMapping> mappings;
  ProjectView view;

  // The JPC settings of one asset whose file unit is `unitScale` cm (for the zero-length
  // rule, 1e-6 file units): the project's alpha and mode, the asset's joints.
  JpcSettings jpcSettings(int asset, double unitScale) const;
  // Every level's motion threshold (level 0's is 0), cm·degrees.
  std::vector<double> levelThresholds() const;
  int levelCount() const { return static_cast<int>(lods.levels.size()); }

  // Rules: alpha finite and >= 0; at most kMaxProjectLevels levels; the LodSet validates (LodSet::validate(): level 0
  // the original, names unique ...), and so does every asset's own set, with at most kMaxProjectLevels levels; no joint
  // overrides level 0's threshold; every asset has a path of at most kMaxAssetPathBytes and a unit scale finite and >=
  // 0; joint names at most kMaxJointNameBytes; every per-joint alpha and threshold finite and >= 0; every mapping names
  // two different assets of the project.
  Error validate() const;

  friend bool operator==(const Project&, const Project&) = default;
};

// The project as JSON text (version kProjectVersion).
std::string projectToJson(const Project& project, int indent = 2);
// Reads what projectToJson() wrote. Errors: not JSON, not a project, a version newer than
// kProjectVersion ("made by a newer Motion LOD Studio"), a missing or mistyped field, or
// values that do not validate.
Result<Project> projectFromJson(std::string_view text);

// Where a project's assets may be (issue 29: `../../../../etc/passwd` was followed and read).
// An absolute asset path is its author's explicit choice and is always followed. A relative
// one must stay inside the project's folder: lexically ("a/../../b" leaves it) and, for what
// exists of it, once symlinks are followed (a link in the folder pointing elsewhere leaves it
// too). One that leaves is refused unless the user allowed it (the CLI's
// --allow-outside-assets, the studio's confirmation).
struct ProjectFileOptions {
  bool allowOutsideAssets = false; // follow relative asset paths that leave the project's folder
};

// Reads a .mlod file (errors name what is wrong, never the project's path: callers add it): a
// regular file of at most kMaxProjectFileBytes (runtime/input_file.h), at most
// kMaxProjectLevels levels, its relative asset paths inside its folder (checkAssetPaths())
// unless options allow otherwise.
Result<Project> loadProjectFile(const std::filesystem::path& file, const ProjectFileOptions& options = {});
// The first asset of `project` (saved at `projectFile`) whose relative path leaves the
// project's folder, named with its index, its stored path and where it leads; none: no error.
Error checkAssetPaths(const Project& project, const std::filesystem::path& projectFile);

// An asset path as stored in a project saved at `projectFile`, with '/' separators: relative
// to its folder when the file is inside it (as checkAssetPaths() sees it), else absolute, so
// that every project saved opens without asking.
std::string storedAssetPath(const std::filesystem::path& projectFile, const std::filesystem::path& assetFile);
// The file a stored path names for a project at `projectFile` (lexically normal; no check:
// loadProjectFile() made it).
std::filesystem::path resolveAssetPath(const std::filesystem::path& projectFile, const std::string& stored);

// Removes / inserts an asset; mappings follow their assets (those of a removed one go).
void eraseProjectAsset(Project& project, int index);
void insertProjectAsset(Project& project, int index, ProjectAsset asset);

// A project's levels after an edit of the level list: per-joint threshold overrides follow
// their level. `order[i]` is the old index of new level i, or -1 for a new level; `levels`
// are the new levels (same size as `order`).
void remapLevels(Project& project, const std::vector<int>& order, const std::vector<LodLevel>& levels);
// The suffix of project files; a file is read as a project wherever the CLI or the editor
// accepts one when its name ends with it.
inline constexpr const char* kProjectSuffix = ".mlod";
inline bool isProjectFile(std::string_view file) {
  return file.ends_with(kProjectSuffix);
}

// A level edit (core/lod/lod_levels.h) applied to the project: its LodSet replaced by
// edit.lods, the per-joint overrides following their level through edit.order.
void applyLodSetEdit(Project& project, const LodSetEdit& edit);

// Whether a mapping of the project plays motion `motion` on character `character`.
bool isMappedOnto(const Project& project, int motion, int character);
// The file name of asset `asset` as the project stores it ("BCN_Epileptic.X"); empty for an
// index out of range.
std::string assetFileName(const Project& project, int asset);

// The asset whose LOD set `asset` plays with (docs/architecture.md section 3: a clip plays
// with the set of the character it is mapped to): for a motion mapped onto characters, the
// character it is viewed on (`viewedCharacter`: the studio's viewport choice) when the motion
// is mapped onto it, else its first mapping's character; for any other asset, the asset
// itself; -1 for an index out of range. A viewed character the motion is not mapped onto (-1:
// on its own skeleton, or none chosen) is ignored.
int lodSetOwner(const Project& project, int asset, int viewedCharacter = -1);
// Whether asset `asset` plays with the set that `owner` owns (an owner as lodSetOwner() gives
// it): it is the owner, or a motion mapped onto it (on any of its mappings: viewed there, it
// plays with that set). The assets whose per-joint overrides are per level of that set.
bool playsWithSetOf(const Project& project, int asset, int owner);
// The LOD set asset `asset` plays with (docs/architecture.md section 3: a character owns its
// set): its owner's own (lodSetOwner(project, asset, viewedCharacter)), else the project's
// (also for an index out of range, -1 included). The one place that rule lives: packages, the
// studio's level docks, crowd and viewport read it.
const LodSet& lodSetFor(const Project& project, int asset, int viewedCharacter = -1);
// Every level's motion threshold of lodSetFor(project, asset, viewedCharacter) (level 0's is
// 0), cm·degrees.
std::vector<double> levelThresholdsFor(const Project& project, int asset, int viewedCharacter = -1);
// The per-joint overrides that `generated` (levels made for asset `asset`, to replace the set
// it plays with: LodSet::fromPixelBudget()) leaves above their level's E, for the Budget
// dialog to list: of every asset that plays with that set (playsWithSetOf(): the character and
// the motions mapped onto it; issue 26: a mapped clip's overrides of 30 and 50 above a
// level of E = 2 went unlisted), each override above the E of its own level in `generated`
// (overridesAboveLevels()), and each at a level `generated` has not (`beyond`: dropped with
// it). By asset, then level, then joint name; `asset` named by its file name.
std::vector<LodOverrideAbove> overridesAboveGeneratedLevels(const Project& project, int asset, const LodSet& generated);
// Every per-joint threshold override of the assets that play with asset `asset`'s set, at any level.
int overrideCountFor(const Project& project, int asset);
// A level edit of the set asset `asset` plays with (viewed on `viewedCharacter`, as
// lodSetOwner()): its owner gets its own set (a copy of what it played with, edited), and the
// per-joint overrides of every asset playing with that set (playsWithSetOf()) follow their
// level; other assets keep theirs. An asset out of range (-1: none in view) edits the
// project's set, as applyLodSetEdit().
void applyLodSetEdit(Project& project, int asset, const LodSetEdit& edit, int viewedCharacter = -1);

} // namespace mlod
