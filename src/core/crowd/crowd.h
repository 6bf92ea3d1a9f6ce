#pragma once
// The crowd the studio previews (docs/architecture.md section 7, "Crowd"; Ahn & Wohn, section 6.2:
// "the detail of the motion and the geometry [chosen] by the distance between the camera and
// the character's position"): N agents of one character on a grid or scattered, each playing
// the clip from its own time offset, each at the LOD level the runtime's selection gives it
// (lod_selection.h, with hysteresis), posed by the runtime's PoseEvaluatorJob, one job per
// level (each level has its own reduced skeleton). What a frame costs is counted here, so
// the editor only draws: agents per level, joints evaluated against full detail, vertices
// skinned, and the CPU time of pose evaluation.
//
// Units: cm, seconds. Y is up (the ground is the XZ plane).

#include "core/clip.h"
#include "core/error.h"
#include "core/jpc/cluster_set.h"
#include "core/jpc/jpc_settings.h"
#include "core/lod/lod_set.h"
#include "core/skeleton.h"
#include "core/skinned_mesh.h"
#include "runtime/lod_clip.h"
#include "runtime/lod_selection.h"
#include "runtime/pose_evaluator.h"
#include "runtime/skinning_job.h"
#include "runtime/worker_pool.h"

#include <glm/glm.hpp>

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

namespace mlod {

// One LOD level as the crowd plays and draws it.
struct CrowdLevel {
  Skeleton skeleton;                      // the level's skeleton (bones reduced)
  std::vector<std::int16_t> parents;      // of `skeleton`
  std::vector<glm::mat4> inverseBinds;    // paletteInverseBinds(skeleton)
  LodClip clip;                           // the level's motion (clusters on the reduced joints), looping
  Clip motion;                            // what `clip` is built from (Crowd::setBlendFrames() builds it again:
  std::optional<ClusterSet> clusters;     // the clip stores its unfreeze windows)
  SkinnedMesh mesh;                       // the level's mesh; bone capsules for a skeleton without mesh
  bool capsules = false;                  // `mesh` is bone capsules (no character mesh)
  int fullDetailSampled = 0;              // joints a full-detail character samples per frame
};

// The levels of `lods` for `skeleton` playing `clip` (which must validate against it) with
// `mesh` (null or a mesh that is not skinned: bone capsules are drawn instead): level i
// clusters at its motion threshold with the JPC settings (per-joint overrides of level i),
// removes the bones frozen throughout, and keeps levels[i].meshRatio of the triangles
// (LodCharacter::build). `cancel` (may be null) is polled between levels.
// Errors: invalid inputs, or a level that cannot be built; "cancelled" when cancelled.
Result<std::vector<CrowdLevel>> buildCrowdLevels(const Skeleton& skeleton, const SkinnedMesh* mesh, const Clip& clip,
                                                 const LodSet& lods, const JpcSettings& jpc = {},
                                                 const std::atomic<bool>* cancel = nullptr);

// A level at full detail alone (the original skeleton, clip and mesh, nothing simplified).
Result<CrowdLevel> buildOriginalCrowdLevel(const Skeleton& skeleton, const SkinnedMesh* mesh, const Clip& clip);
// A level of the original skeleton and mesh playing `clip` with `clusters` (null: full
// detail), no bone removed: what `motionlod bench-crowd FILE --threshold E` compares.
// Errors: as buildOriginalCrowdLevel(), clusters that do not fit the clip.
Result<CrowdLevel> buildCrowdLevel(const Skeleton& skeleton, const SkinnedMesh* mesh, const Clip& clip,
                                   const ClusterSet* clusters);

// Where the agents stand.
struct CrowdLayout {
  enum class Kind : std::uint8_t { Grid, Scattered };
  Kind kind = Kind::Grid;
  int agents = 100;          // 1 to kMaxCrowdAgents
  float spacingCm = 200.0f;  // grid step; scattered agents fill the same square area
  std::uint32_t seed = 1;    // scattered positions, yaws and time offsets
  bool randomOffsets = true; // each agent its own time offset in [0, period); false: all 0
};
inline constexpr int kMaxCrowdAgents = 10000;

struct CrowdAgent {
  glm::vec3 position{0.0f}; // on the ground, cm; the grid is centred on the origin
  float yawRadians = 0.0f;  // about +Y
  double timeOffset = 0.0;  // seconds
};

// The agents of `layout` for a clip of `periodSeconds` (>= 0). Deterministic for a seed.
// Grid: a square of ceil(sqrt(N)) columns, row by row. Scattered: uniform in that square.
std::vector<CrowdAgent> layoutCrowd(const CrowdLayout& layout, double periodSeconds);

// The runtime selection's view of a LodSet: the levels that can be reached and the
// boundaries between them (lod_selection.h wants them strictly ascending distances or
// strictly descending sizes, > 0). A level whose switch distance equals the next one's is
// never used (the next takes over at the same distance), so it is left out; so is level 0
// when level 1 switches in at distance 0.
struct LodSwitches {
  std::vector<int> levels;       // LodSet level of each selection level, ascending
  std::vector<float> boundaries; // levels.size() - 1 entries
};
LodSwitches lodSwitchesByDistance(const LodSet& lods);
LodSwitches lodSwitchesByScreenSize(const LodSet& lods);

// Figures of the last update().
struct CrowdFrameStats {
  std::vector<int> agentsPerLevel; // indexed by crowd level (= LodSet level)
  std::int64_t jointsEvaluated = 0;  // joints whose local matrix was computed (PoseEvaluatorContext::jointsSampled)
  std::int64_t jointsFullDetail = 0; // what every agent at full detail would have computed
  std::int64_t verticesSkinned = 0;  // vertices of each agent's level mesh, summed
  double poseCpuMs = 0.0;            // CPU time of the selection and pose evaluation (this thread), ms
  double poseMs = 0.0;               // wall-clock time of the selection and pose evaluation, ms
  double skinMs = 0.0;               // wall-clock time of CPU skinning (setSkinning()), ms; 0 without
};

// The front of a crowd as the studio's Crowd dock frames it: standing before the agents'
// nearest row (smallest z), at the middle of its width, raised and looking in along +Z, so
// that the nearest agents are a few metres away and the farthest at the far edge. cm.
glm::vec3 crowdFrontCamera(std::span<const CrowdAgent> agents);

// A crowd: levels, agents, and per frame their levels and skinning palettes.
class Crowd {
public:
  struct Selection {
    LodSelectionJob::Mode mode = LodSelectionJob::Mode::Distance;
    float hysteresis = 0.1f;       // [0, 1)
    ScreenProjection projection;   // ScreenSize mode
    float boundingRadiusCm = 100.0f; // ScreenSize mode
    int forcedLevel = -1;          // >= 0: every agent at this level (clamped), no selection
  };

  // `levels` (at least one; level 0 the original). Forgets the agents' levels and state.
  void setLevels(std::vector<CrowdLevel> levels);
  // Threads that pose evaluation and skinning spread agents over (>= 1; 1 = the calling
  // thread alone). Forgets the agents' state.
  void setThreads(int threads);
  int threads() const { return m_pool ? m_pool->threadCount() : 1; }
  // Skin every agent's level mesh on the CPU in update() with the runtime's SkinningJob, as
  // a renderer without GPU skinning does (what the paper's Figure 12 times); the skinned
  // vertices are scratch. (A level mesh that SkinningMesh refuses fails update().)
  void setSkinning(bool on) { m_skin = on; }
  // Write each agent's model matrices too (levelModels()), as well as its palette.
  void setModels(bool on) { m_writeModels = on; }
  // Frames over which resuming joints blend back (PoseEvaluatorJob::blendFrames; 0 = off,
  // the default): the levels' clips with clusters are built again for it (they store their
  // unfreeze windows; LodClip's header). Forgets the agents' state.
  void setBlendFrames(int frames);
  void setAgents(std::vector<CrowdAgent> agents);
  void setSelection(const Selection& selection) { m_selection = selection; }
  // Where the LOD set switches (lodSwitchesBy...(): levels as crowd level indices).
  void setSwitches(LodSwitches distance, LodSwitches screenSize);

  int levelCount() const { return static_cast<int>(m_levels.size()); }
  const CrowdLevel& level(int index) const { return m_levels[static_cast<std::size_t>(index)]; }
  const std::vector<CrowdAgent>& agents() const { return m_agents; }
  int agentCount() const { return static_cast<int>(m_agents.size()); }
  // The point whose distance to the camera decides an agent's level: its position raised by
  // `centreHeight` (cm; set from the character's bounding box by the caller).
  void setCentreHeight(float cm) { m_centreHeight = cm; }
  glm::vec3 agentCentre(int agent) const;

  // Selects every agent's level for a camera at `camera` (cm) and evaluates the poses of
  // all agents at global time `seconds` (each at seconds + its offset), then skins them
  // (setSkinning()). Errors: no levels, a runtime job that refuses its inputs, a level mesh
  // that cannot be skinned.
  Error update(double seconds, const glm::vec3& camera);

  // After update(): each agent's level, the agents of a level (ascending), and a level's
  // palettes ([k * joints + j] for the k-th agent of levelAgents(level)).
  int agentLevel(int agent) const { return m_agentLevel[static_cast<std::size_t>(agent)]; }
  std::span<const int> levelAgents(int level) const { return m_levelAgents[static_cast<std::size_t>(level)]; }
  std::span<const glm::mat4> levelPalettes(int level) const { return m_palettes[static_cast<std::size_t>(level)]; }
  // With setModels(true): a level's model matrices, laid out as its palettes.
  std::span<const glm::mat4> levelModels(int level) const { return m_models[static_cast<std::size_t>(level)]; }
  const CrowdFrameStats& stats() const { return m_stats; }

private:
  struct SkinTask {
    const SkinningMesh* mesh = nullptr;
    const glm::mat4* palettes = nullptr;
    std::size_t joints = 0;
    Crowd* crowd = nullptr;
    std::atomic<bool> failed{false};
  };
  static void skinAgents(void* data, int begin, int end, int thread);

  std::vector<CrowdLevel> m_levels;
  std::vector<CrowdAgent> m_agents;
  Selection m_selection;
  LodSwitches m_distance, m_size;
  float m_centreHeight = 0.0f;
  std::vector<std::int32_t> m_selected;   // per agent: selection level (index into switches), -1 none
  LodSelectionJob::Mode m_selectedMode = LodSelectionJob::Mode::Distance;
  std::vector<int> m_agentLevel;          // per agent: crowd level
  std::vector<std::vector<int>> m_levelAgents;
  std::vector<std::vector<glm::mat4>> m_palettes;
  std::vector<std::vector<glm::mat4>> m_models;
  bool m_writeModels = false;
  int m_blendFrames = 0;
  std::unique_ptr<WorkerPool> m_pool;
  bool m_skin = false;
  std::vector<std::optional<SkinningMesh>> m_skinning; // per level, with skinning on
  std::vector<std::vector<glm::vec3>> m_skinPositions; // per thread
  std::vector<std::vector<glm::vec3>> m_skinNormals;
  std::vector<PoseEvaluatorContext> m_contexts; // per level, per agent slot
  std::vector<std::vector<int>> m_slotAgent;    // per level: the agent whose state each context slot holds
  std::vector<glm::vec3> m_centres;
  std::vector<float> m_radii;
  std::vector<const LodClip*> m_clips;
  std::vector<double> m_times;
  CrowdFrameStats m_stats;
};

// The paper's Figure 12 on one crowd (docs/architecture.md sections 5 and 6): the same agents,
// camera and frames played in four configurations, each frame pose evaluation plus CPU
// skinning of every agent (Crowd::setSkinning(); `skinning` false: pose evaluation alone, what
// an engine's CPU pays when the GPU skins): "none" (every agent at level 0),
// "skeletal" (the levels' motion with level 0's mesh: every mesh ratio 1), "mesh" (level
// 0's motion with the levels' meshes: every threshold 0) and "both" (the LOD set as it is).
// Levels are picked by distance with hysteresis from the LOD set's switch distances.
struct CrowdComparisonSettings {
  int frames = 60;                 // per repetition, >= 1
  double frameSeconds = 1.0 / 60.0; // clip time between frames
  double startSeconds = 0.0;       // clip time of the first frame
  int repetitions = 3;             // >= 1; figures are medians
  int threads = 1;                 // >= 1
  float centreHeightCm = 0.0f;     // Crowd::setCentreHeight()
  JpcSettings jpc;                 // for the levels' motion
  const std::atomic<bool>* cancel = nullptr; // polled between builds and repetitions
  bool skinning = true;                      // skin every agent on the CPU; false: pose evaluation alone
  // Also time the crowd of "both" with every agent forced to level k, for each level, the
  // levels alternating within each repetition: CrowdComparison::levelFrameMs and levelCost.
  bool levelCosts = false;
};
struct CrowdConfigurationFigures {
  const char* name = "";           // none, skeletal, mesh, both
  double frameMs = 0.0;            // pose + skin per frame, median of the repetitions
  double poseMs = 0.0;             // medians of each
  double skinMs = 0.0;
  double jointsEvaluated = 0.0;    // per frame
  double verticesSkinned = 0.0;    // per frame
  std::vector<double> repetitionFrameMs;
  std::vector<int> agentsPerLevel; // at the last frame
  // LodClip::byteSize() of every clip the configuration's agents read (the levels any agent
  // stood at in any timed frame), each clip once: levels of equal motion threshold and no
  // per-joint override there play the same motion (the "mesh" configuration's levels all
  // play level 0's), so they count one clip.
  std::size_t clipBytes = 0;
};
struct CrowdComparison {
  CrowdConfigurationFigures configurations[4]; // none, skeletal, mesh, both
  // The levels of "both": triangles, vertices and joints of each.
  struct Level {
    std::size_t triangles = 0, vertices = 0;
    int joints = 0;
  };
  std::vector<Level> levels;
  double clipSeconds = 0.0; // the clip's duration (LodClip::duration(), level 0's), s
  // With CrowdComparisonSettings::levelCosts, per level of "both": the frame time (ms, pose +
  // skin, median of the repetitions) with every agent at that level, and that time over level
  // 0's (what an agent at level k costs as a fraction of a LOD0 agent); else empty.
  std::vector<double> levelFrameMs;
  std::vector<double> levelCost;
  // none.frameMs / configuration i's frameMs (1 for none itself).
  double speedup(int i) const {
    return configurations[i].frameMs > 0.0 ? configurations[0].frameMs / configurations[i].frameMs : 0.0;
  }
  // The median and range of a figure over the repetitions.
  struct Spread {
    double median = 0.0, min = 0.0, max = 0.0;
    int samples = 0;
  };
  // Configuration i's frame time (ms) over the repetitions.
  Spread frameMsSpread(int i) const;
  // Per repetition, none's frame time over configuration i's in that same repetition (the
  // configurations alternate, so a repetition's four share the machine's load): their
  // median and range. A spread much wider than the median says the machine was busy.
  Spread speedupSpread(int i) const;
};
// Errors: what buildCrowdLevels() and Crowd::update() report; "cancelled".
Result<CrowdComparison> compareCrowdConfigurations(const Skeleton& skeleton, const SkinnedMesh* mesh, const Clip& clip,
                                                   const LodSet& lods, std::span<const CrowdAgent> agents,
                                                   const glm::vec3& camera, const CrowdComparisonSettings& settings);

// A low-poly capsule along every bone (joint to parent, `radiusCm` thick, at most a fifth
// of the bone's length), rigidly skinned to the parent joint, in the skeleton's rest pose:
// what the views draw for a skeleton without a mesh. Bones shorter than 1e-3 cm are left
// out; a skeleton of one joint gets a small sphere-like capsule at the root.
SkinnedMesh boneCapsuleMesh(const Skeleton& skeleton, float radiusCm);

} // namespace mlod
