#pragma once
// LOD levels of one character (docs/architecture.md section 3): a list of levels, each with a motion
// threshold, a mesh reduction, and the camera distance (and screen size) from which it is
// used, under the projection its pixel figures assume. Level 0 is the original.
//
// One error budget (docs/architecture.md section 5): fromPixelBudget() generates the levels so that
// each stays within N pixels on screen, its switch distance coming from what it measures.
// With a mesh, the mesh leads: level i's ratio is spread in log scale from 1 down to the
// smallest candidate ratio (4 levels: 50%, 20%, 10%), so the far levels are the coarse ones;
// the ratio's measured mesh error (bind pose and animated frames the simplification did not
// see, mesh_lod.h) sets the level's deviation delta_i = mesh error / (1 - motionShare), and
// the motion takes the largest candidate threshold whose motion error stays within
// motionShare x delta_i (bone reduction included, lod_character.h; where that would repeat
// the previous level's threshold, the largest whole threshold below the first candidate that
// misses); motionShare is what the character's CPU pays for its motion: where the GPU skins
// (LodSkinning::Gpu, the default, as engines do) the CPU pays the pose alone and the motion
// takes kGpuMotionShare (a half); where the CPU skins (LodSkinning::Cpu) the pose's share of
// the character's frame cost (motionShareByCost()). Without a mesh, level i is aimed at the
// distance where the character's bounding sphere covers height / 2^i pixels (half the
// screen, a quarter ...), where N pixels allow a deviation delta_i (error_budget.h) for the
// motion. Either way the level switches in at the smallest distance where its measured
// deviation (motion + the mesh error of its own rebound mesh) spans at most N pixels: never
// nearer than the previous level's. A level whose threshold is 0 (the original's motion) or
// that repeats the level kept before it (same threshold and mesh ratio) is left out and
// reported, so a set may hold fewer levels than asked. Every figure stays editable;
// validate() checks an edited set.
//
// Units: thresholds in cm·degrees, lengths and errors in cm, sizes and errors on screen in
// pixels.

#include "core/asset.h"
#include "core/clip.h"
#include "core/error.h"
#include "core/jpc/jpc_settings.h"
#include "core/jpc/work_budget.h"
#include "core/lod/error_budget.h"
#include "core/lod/lod_budget_cache.h"
#include "core/mesh/mesh_lod.h"

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace mlod {

// The longest level name, in bytes (UTF-8): names are labels in tables and charts, and a
// 100,000-character one made the studio lay it out for half a minute (issue 29).
inline constexpr std::size_t kMaxLevelNameBytes = 256;

struct LodLevel {
  std::string name;              // unique in its set, at most kMaxLevelNameBytes
  double motionThreshold = 0.0;  // E, cm·degrees; 0 at level 0
  double meshRatio = 1.0;        // triangles kept, (0, 1]
  double switchDistanceCm = 0.0; // the level is used from this camera distance on; 0 at level 0
  double pixelError = 0.0;       // the most its deviation spans on screen from the switch distance on, px
  double screenSizePixels = 0.0; // the character's projected height at the switch distance (0 at level 0)
  // What the generator measured (left as they are when a user edits a level):
  double motionErrorCm = 0.0; // skin displacement by the level's motion, max over every frame
  double meshErrorCm = 0.0;   // the level mesh's error, max over bind and animated poses
  int triangles = 0;          // of the level's mesh (0 without a mesh)
  int activeJoints = 0;       // joints left after bone reduction
  double deviationCm() const { return motionErrorCm + meshErrorCm; }
  friend bool operator==(const LodLevel&, const LodLevel&) = default;
};

// Where a character's skinning runs, which decides what its frame costs the CPU and so the
// motion's share of each level's deviation (LodBudgetOptions::skinning). Saved with the set
// it generated (LodSet::skinning; a project's "skinning": "gpu" | "cpu").
enum class LodSkinning : std::uint8_t {
  Gpu, // the GPU skins: the CPU pays the pose alone (engines; the default)
  Cpu, // the CPU skins every vertex (the paper's Figure 12, `motionlod bench-crowd --scene`)
};
// "gpu" / "cpu": the project file's and the command line's spelling.
const char* lodSkinningName(LodSkinning skinning);
// Reads "gpu" or "cpu" (exactly, lower case); nullopt for anything else.
std::optional<LodSkinning> lodSkinningFromName(std::string_view name);

struct LodBudgetOptions {
  // Clips of the asset's skeleton besides its own (mapped motions, retargetClip()); every
  // level must hold for them too.
  std::span<const Clip> clips;
  JpcSettings jpc;
  MeshLodSettings mesh;
  LodProjection projection;
  // Where the character is skinned; it sets the motion's share below when that is unset.
  LodSkinning skinning = LodSkinning::Gpu;
  // (0, 1]: of each level's deviation (with a mesh), the part the motion may take first;
  // unset: with LodSkinning::Gpu, kGpuMotionShare; with LodSkinning::Cpu, the motion's share
  // of the character's frame cost at level 0, between kMinMotionShare and kMaxMotionShare
  // (motionShareByCost()).
  std::optional<double> motionShare;
  // The thresholds tried for the motion (cm·degrees, ascending): the paper's Table 1 values and
  // the steps between.
  std::vector<double> thresholds = {0.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0, 200.0, 300.0, 500.0, 1000.0};
  // The mesh ratios the levels take (falling, each in (0, 1]; the last is the coarsest level's).
  std::vector<double> meshRatios = {0.9, 0.8, 0.7, 0.6, 0.5, 0.4, 0.3, 0.25, 0.2, 0.15, 0.1};
  // Called on the generating thread with the fraction of the work done, in [0, 1], rising;
  // returning false cancels: fromPixelBudget() then returns kLodBudgetCancelled at once.
  std::function<bool(double fraction)> progress;
  // Run-time only, never saved or compared (core/cancel.h; may be null; else it replaces
  // mesh.cancel): once set, every step of the search (JPC per joint, the progressive mesh,
  // the poses measured) stops and fromPixelBudget() returns kLodBudgetCancelled within a
  // fraction of a second. What the CLI's Ctrl+C and the studio's Cancel set.
  const std::atomic<bool>* cancel = nullptr;
  // The clustering work the whole search may spend (core/jpc/work_budget.h units, every
  // threshold tried, every clip and joint together); past it fromPixelBudget() refuses the
  // character, naming the limit (LodCharacter::motionAt()).
  std::int64_t workLimit = kMaxJpcWork;
  // Run-time only, never saved or compared (may be null): what earlier runs on this character
  // computed, reused and added to (lod_budget_cache.h); the levels are the same either way.
  LodBudgetCache* cache = nullptr;
};

// The deviation a level may spend goes where it buys frame time (docs/architecture.md
// section 5). Skinned on the GPU (LodSkinning::Gpu), the CPU's bill is the pose alone, the
// mesh's cost is the GPU's, and neither bill says how to split the deviation between them:
// the motion takes a stated half (kGpuMotionShare), enough for thresholds whose clusters
// are long (with 5%, BCN_Epileptic's levels took E = 1, 2, 5: clusters so short that
// skipping them saved nothing, issue 25). Skinned on the CPU (LodSkinning::Cpu), a
// character's frame costs pose evaluation (about kPoseCostPerJoint per joint:
// 3,115 instructions for CMU 01_01's 38 joints, callgrind on this runtime) plus CPU skinning
// (about kSkinCostPerVertex per vertex: 29.4 on BCN_Epileptic), and the motion's share of a
// level's deviation is the pose's share of that cost, clamped to [kMinMotionShare,
// kMaxMotionShare]: the mesh leads, and at least 5% keeps a threshold above 0 within reach
// (at 2%, BCN_Epileptic's LOD1 finds none and is left out). 54 joints and 3,014 vertices
// (BCN_Epileptic): 4.8%, so 5%; 28 joints and 471 vertices (the paper's crowd): 14%; a
// skeleton without a mesh: the motion takes the whole deviation, whatever skins it.
inline constexpr double kGpuMotionShare = 0.5;
inline constexpr double kPoseCostPerJoint = 82.0;
inline constexpr double kSkinCostPerVertex = 29.4;
inline constexpr double kMinMotionShare = 0.05;
inline constexpr double kMaxMotionShare = 0.5;
double motionShareByCost(int joints, std::size_t vertices);

inline constexpr const char* kLodBudgetCancelled = "LOD: level generation cancelled";

// What fromPixelBudget() found besides the set: what the editor's Budget dialog previews.
struct LodBudgetReport {
  // Per level of the set: 100 x clustered joint-frames / (clusterable joints x frames) over
  // every clip the level plays (0 at level 0; the paper's Table 1 figure).
  std::vector<double> simplifiedPercent;
  // The aimed levels left out (an E of 0, or a repeat of the level before), one line each.
  std::vector<std::string> dropped;
  // The motion's share of each level's deviation that was used (LodBudgetOptions::motionShare,
  // else kGpuMotionShare or motionShareByCost() by LodBudgetOptions::skinning; 1 without a
  // mesh: the motion takes all of it; 0 without a clip).
  double motionShare = 0.0;
  // The work this run did (statistics; with LodBudgetOptions::cache, what it could not reuse):
  int jointsClustered = 0;        // joint clusterings made
  int motionsMade = 0;            // level motions made (bone reduction, clips, motion error)
  int meshesBuilt = 0;            // progressive meshes built
  bool characterPrepared = false; // the character's JPC tracks and bounding radius computed
};

class LodSet {
public:
  LodProjection projection;
  LodSkinning skinning = LodSkinning::Gpu; // what the levels' budget split assumed (LodBudgetOptions::skinning)
  double boundingRadiusCm = 0.0; // about the root, holding the posed character in every frame
  std::vector<LodLevel> levels;

  // Up to `levels` levels (>= 1, level 0 the original) within `pixels` (> 0) on screen, for
  // the asset's character mesh (its first skinned mesh; none: the joints) and skeleton
  // playing the asset's clips and options.clips. Without a clip (or a skeleton) the levels
  // are the mesh's alone, measured in its bind pose (every threshold 0: only the repeat rule
  // applies). `report`, when given, receives the figures of the preview. Errors: an asset
  // with neither a clip nor a mesh, bad options, a cancel (kLodBudgetCancelled).
  static Result<LodSet> fromPixelBudget(const Asset& asset, double pixels, int levels, const LodBudgetOptions& options,
                                        LodBudgetReport* report = nullptr);
  // With the default options (the asset's own clips, default JPC and mesh settings).
  static Result<LodSet> fromPixelBudget(const Asset& asset, double pixels, int levels);

  // Rules: the projection validates; at least one level; level 0 has threshold 0, ratio 1
  // and distance 0; thresholds finite >= 0; ratios in (0, 1]; switch distances finite,
  // >= 0 and non-decreasing; pixel errors and screen sizes finite >= 0; names unique and at
  // most kMaxLevelNameBytes long.
  Error validate() const;

  friend bool operator==(const LodSet&, const LodSet&) = default;
};

} // namespace mlod
