#include "core/crowd/crowd.h"

#include "core/lod/lod_character.h"
#include "core/lod_clip_builder.h"

#include <glm/gtc/constants.hpp>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <limits>
#include <random>
#include <string>

namespace mlod {

namespace {

// CPU time of the calling thread, seconds: the crowd's figure is what pose evaluation costs,
// not what the rest of a busy machine does meanwhile.
double threadCpuSeconds() {
#if defined(CLOCK_THREAD_CPUTIME_ID)
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
#else
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
#endif
}

// A capsule radius for a skeleton: 3% of its rest extent, at least 0.5 cm.
float capsuleRadiusFor(const Skeleton& skeleton) {
  const std::vector<glm::mat4> rest = skeleton.restModelMatrices();
  glm::vec3 lo(0.0f), hi(0.0f);
  for (std::size_t i = 0; i < rest.size(); ++i) {
    const glm::vec3 p(rest[i][3]);
    lo = i == 0 ? p : glm::min(lo, p);
    hi = i == 0 ? p : glm::max(hi, p);
  }
  return std::max(0.5f, 0.03f * glm::length(hi - lo));
}

Result<CrowdLevel> finishLevel(Skeleton skeleton, const SkinnedMesh* mesh, const Clip& clip, const ClusterSet* clusters,
                               int fullDetailSampled) {
  CrowdLevel level;
  const std::vector<std::int16_t> parents = skeleton.parentIndices();
  Result<LodClip> lod = buildLodClip(clip, clusters, true, parents);
  if (!lod)
    return lod.error();
  level.clip = std::move(lod).value();
  level.motion = clip;
  if (clusters)
    level.clusters = *clusters;
  level.parents = skeleton.parentIndices();
  level.inverseBinds = paletteInverseBinds(skeleton);
  if (mesh && mesh->skinned()) {
    level.mesh = *mesh;
  } else {
    level.mesh = boneCapsuleMesh(skeleton, capsuleRadiusFor(skeleton));
    level.capsules = true;
  }
  level.skeleton = std::move(skeleton);
  level.fullDetailSampled = fullDetailSampled >= 0 ? fullDetailSampled : level.clip.animatedJointCount();
  return level;
}

// A level's clip built for `blendFrames` (a clip without clusters blends nothing: kept).
void buildFor(CrowdLevel& level, int blendFrames) {
  if (level.clip.clusterCount() == 0 || level.clip.blendFrames() == blendFrames)
    return;
  Result<LodClip> built =
      buildLodClip(level.motion, level.clusters ? &*level.clusters : nullptr, true, level.parents, blendFrames);
  if (built) // (it was built from the same inputs before; should it fail, the job refuses the clip's N)
    level.clip = std::move(built).value();
}

} // namespace

Result<CrowdLevel> buildOriginalCrowdLevel(const Skeleton& skeleton, const SkinnedMesh* mesh, const Clip& clip) {
  if (Error error = skeleton.validate())
    return Error("crowd: " + error.message());
  if (Error error = clip.validate(skeleton))
    return Error("crowd: " + error.message());
  if (mesh && mesh->skinned())
    if (Error error = mesh->validate(skeleton.jointCount()))
      return Error("crowd: " + error.message());
  return finishLevel(skeleton, mesh, clip, nullptr, -1);
}

Result<CrowdLevel> buildCrowdLevel(const Skeleton& skeleton, const SkinnedMesh* mesh, const Clip& clip,
                                   const ClusterSet* clusters) {
  Result<CrowdLevel> original = buildOriginalCrowdLevel(skeleton, mesh, clip);
  if (!original || !clusters)
    return original;
  return finishLevel(skeleton, mesh, clip, clusters, original->fullDetailSampled);
}

Result<std::vector<CrowdLevel>> buildCrowdLevels(const Skeleton& skeleton, const SkinnedMesh* mesh, const Clip& clip,
                                                 const LodSet& lods, const JpcSettings& jpc,
                                                 const std::atomic<bool>* cancel) {
  if (Error error = lods.validate())
    return Error("crowd: " + error.message());
  Result<CrowdLevel> original = buildOriginalCrowdLevel(skeleton, mesh, clip);
  if (!original)
    return original.error();
  std::vector<CrowdLevel> out;
  out.push_back(std::move(original).value());
  const int fullDetail = out.front().fullDetailSampled;
  if (lods.levels.size() < 2)
    return out;
  const SkinnedMesh* skinned = mesh && mesh->skinned() ? mesh : nullptr;
  const Clip clips[1] = {clip};
  Result<LodCharacter> character = LodCharacter::prepare(skeleton, skinned, clips, jpc);
  if (!character)
    return Error("crowd: " + character.message());
  for (std::size_t i = 1; i < lods.levels.size(); ++i) {
    if (cancel && cancel->load())
      return Error("cancelled");
    const LodLevel& spec = lods.levels[i];
    Result<LevelBuild> build = character->build(spec.motionThreshold, spec.meshRatio, static_cast<int>(i));
    if (!build)
      return Error("crowd: level " + spec.name + ": " + build.message());
    const LevelMotion& motion = build->motion;
    // The clusters were found on the full skeleton; the reduced skeleton keeps the active
    // joints, whose reduced clip holds the key rotation through each cluster (the removed
    // joints above them are constant), so their clusters carry over as they are.
    ClusterSet reduced;
    reduced.frameCount = clip.frameCount;
    for (int full : motion.bones.fullIndex)
      reduced.joints.push_back(motion.clusters.front().joints[static_cast<std::size_t>(full)]);
    const SkinnedMesh* levelMesh = build->mesh ? &build->mesh->mesh : nullptr;
    Result<CrowdLevel> level = finishLevel(motion.bones.skeleton, levelMesh, motion.clips.front(), &reduced, fullDetail);
    if (!level)
      return Error("crowd: level " + spec.name + ": " + level.message());
    out.push_back(std::move(level).value());
  }
  return out;
}

std::vector<CrowdAgent> layoutCrowd(const CrowdLayout& layout, double periodSeconds) {
  const int count = std::clamp(layout.agents, 1, kMaxCrowdAgents);
  const int columns = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(count))));
  const float spacing = std::isfinite(layout.spacingCm) && layout.spacingCm > 0.0f ? layout.spacingCm : 200.0f;
  const float side = spacing * static_cast<float>(columns - 1);
  const double period = std::isfinite(periodSeconds) && periodSeconds > 0.0 ? periodSeconds : 0.0;
  std::mt19937 random(layout.seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<CrowdAgent> agents(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    CrowdAgent& agent = agents[static_cast<std::size_t>(i)];
    if (layout.kind == CrowdLayout::Kind::Grid) {
      agent.position = glm::vec3(static_cast<float>(i % columns) * spacing - 0.5f * side, 0.0f,
                                 static_cast<float>(i / columns) * spacing - 0.5f * side);
    } else {
      const float x = unit(random), z = unit(random);
      agent.position = glm::vec3((x - 0.5f) * side, 0.0f, (z - 0.5f) * side);
      agent.yawRadians = unit(random) * glm::two_pi<float>();
    }
    if (layout.randomOffsets)
      agent.timeOffset = static_cast<double>(unit(random)) * period;
  }
  return agents;
}

namespace {

LodSwitches switchesFrom(const LodSet& lods, bool bySize) {
  LodSwitches out;
  const std::size_t n = lods.levels.size();
  // start[i]: where level i begins, as a distance (ascending) or a size (descending).
  auto start = [&](std::size_t i) {
    return static_cast<float>(bySize ? lods.levels[i].screenSizePixels : lods.levels[i].switchDistanceCm);
  };
  // Distance: level i is used on [start(i), start(i + 1)), level 0 from 0. Size: on
  // (start(i + 1), start(i)], level 0 from any size; a size of 0 is never reached.
  auto usable = [&](std::size_t i) {
    if (!std::isfinite(start(i)) || (bySize && i > 0 && !(start(i) > 0.0f)))
      return false;
    if (i + 1 == n)
      return true;
    return bySize ? start(i + 1) < start(i) || i == 0 : start(i + 1) > (i == 0 ? 0.0f : start(i));
  };
  for (std::size_t i = 0; i < n; ++i) {
    if (!usable(i))
      continue;
    if (!out.boundaries.empty() &&
        (bySize ? start(i) >= out.boundaries.back() : start(i) <= out.boundaries.back()))
      continue; // out of order (sizes are not checked by LodSet::validate): the earlier level holds
    if (!out.levels.empty())
      out.boundaries.push_back(start(i));
    out.levels.push_back(static_cast<int>(i));
  }
  if (out.levels.empty()) // nothing switches anywhere: the last level everywhere
    out.levels.push_back(static_cast<int>(n) - 1);
  return out;
}

} // namespace

LodSwitches lodSwitchesByDistance(const LodSet& lods) { return switchesFrom(lods, false); }
LodSwitches lodSwitchesByScreenSize(const LodSet& lods) { return switchesFrom(lods, true); }

void Crowd::setLevels(std::vector<CrowdLevel> levels) {
  m_levels = std::move(levels);
  for (CrowdLevel& level : m_levels)
    buildFor(level, m_blendFrames);
  const std::size_t n = m_levels.size();
  m_levelAgents.assign(n, {});
  m_palettes.assign(n, {});
  m_models.assign(n, {});
  m_skinning.clear();
  m_contexts.assign(n, {});
  m_slotAgent.assign(n, {});
  std::fill(m_selected.begin(), m_selected.end(), -1);
  m_stats = {};
}

void Crowd::setAgents(std::vector<CrowdAgent> agents) {
  m_agents = std::move(agents);
  m_selected.assign(m_agents.size(), -1);
  m_agentLevel.assign(m_agents.size(), 0);
  for (auto& slots : m_slotAgent)
    slots.clear();
}

void Crowd::setThreads(int threads) {
  threads = std::max(threads, 1);
  if (threads == this->threads())
    return;
  m_pool = threads > 1 ? std::make_unique<WorkerPool>(threads) : nullptr;
  for (PoseEvaluatorContext& context : m_contexts)
    context = {};
  for (auto& slots : m_slotAgent)
    slots.clear();
}

void Crowd::setBlendFrames(int frames) {
  m_blendFrames = std::clamp(frames, 0, kMaxBlendFrames);
  for (CrowdLevel& level : m_levels)
    buildFor(level, m_blendFrames); // the N the level is played with (PoseEvaluatorJob checks it)
  for (auto& slots : m_slotAgent)
    slots.clear();
  for (PoseEvaluatorContext& context : m_contexts)
    context.reset();
}

void Crowd::setSwitches(LodSwitches distance, LodSwitches screenSize) {
  m_distance = std::move(distance);
  m_size = std::move(screenSize);
  std::fill(m_selected.begin(), m_selected.end(), -1);
}

glm::vec3 Crowd::agentCentre(int agent) const {
  return m_agents[static_cast<std::size_t>(agent)].position + glm::vec3(0.0f, m_centreHeight, 0.0f);
}

Error Crowd::update(double seconds, const glm::vec3& camera) {
  if (m_levels.empty())
    return Error("crowd: no levels");
  if (m_skin && m_skinning.size() != m_levels.size()) {
    m_skinning.clear();
    std::size_t vertices = 0;
    for (const CrowdLevel& level : m_levels) {
      Result<SkinningMesh> built = buildSkinningMesh(level.mesh, static_cast<int>(level.parents.size()));
      if (!built)
        return Error("crowd: " + built.message());
      vertices = std::max(vertices, static_cast<std::size_t>(built->vertexCount()));
      m_skinning.emplace_back(std::move(built).value());
    }
    const std::size_t threads = static_cast<std::size_t>(this->threads());
    m_skinPositions.assign(threads, std::vector<glm::vec3>(vertices));
    m_skinNormals.assign(threads, std::vector<glm::vec3>(vertices));
  }
  const double cpuStart = threadCpuSeconds();
  const auto wallStart = std::chrono::steady_clock::now();
  const std::size_t agents = m_agents.size();
  const int levels = levelCount();

  // Levels: the runtime's selection, with hysteresis from the agents' previous levels.
  if (m_selection.forcedLevel >= 0) {
    std::fill(m_agentLevel.begin(), m_agentLevel.end(), std::min(m_selection.forcedLevel, levels - 1));
    std::fill(m_selected.begin(), m_selected.end(), -1);
  } else {
    const bool bySize = m_selection.mode == LodSelectionJob::Mode::ScreenSize;
    if (bySize != (m_selectedMode == LodSelectionJob::Mode::ScreenSize))
      std::fill(m_selected.begin(), m_selected.end(), -1); // the other mode's levels mean nothing here
    m_selectedMode = m_selection.mode;
    const LodSwitches& switches = bySize ? m_size : m_distance;
    if (switches.levels.empty())
      return Error("crowd: no LOD switches set");
    m_centres.resize(agents);
    for (std::size_t a = 0; a < agents; ++a)
      m_centres[a] = agentCentre(static_cast<int>(a));
    m_radii.assign(bySize ? agents : 0, m_selection.boundingRadiusCm);
    LodSelectionJob job;
    job.mode = m_selection.mode;
    job.camera = camera;
    job.positions = m_centres;
    job.radii = m_radii;
    job.boundaries = switches.boundaries;
    job.hysteresis = m_selection.hysteresis;
    job.projection = m_selection.projection;
    job.inout_levels = m_selected;
    if (!job.run())
      return Error("crowd: the LOD selection refused its inputs (switch distances or sizes out of order?)");
    for (std::size_t a = 0; a < agents; ++a)
      m_agentLevel[a] = std::min(switches.levels[static_cast<std::size_t>(m_selected[a])], levels - 1);
  }

  // Poses: one job per level over the agents at that level.
  for (auto& list : m_levelAgents)
    list.clear();
  for (std::size_t a = 0; a < agents; ++a)
    m_levelAgents[static_cast<std::size_t>(m_agentLevel[a])].push_back(static_cast<int>(a));
  m_stats.agentsPerLevel.assign(static_cast<std::size_t>(levels), 0);
  m_stats.jointsEvaluated = 0;
  m_stats.jointsFullDetail = 0;
  m_stats.verticesSkinned = 0;
  for (int l = 0; l < levels; ++l) {
    const std::size_t li = static_cast<std::size_t>(l);
    const CrowdLevel& level = m_levels[li];
    const std::vector<int>& list = m_levelAgents[li];
    const std::size_t count = list.size();
    m_stats.agentsPerLevel[li] = static_cast<int>(count);
    m_stats.jointsFullDetail += static_cast<std::int64_t>(count) * level.fullDetailSampled;
    m_stats.verticesSkinned += static_cast<std::int64_t>(count) * static_cast<std::int64_t>(level.mesh.vertexCount());
    if (count == 0)
      continue;
    const std::size_t joints = level.parents.size();
    PoseEvaluatorContext& context = m_contexts[li];
    std::vector<int>& slots = m_slotAgent[li];
    if (context.characterCount() < static_cast<int>(count) || context.threadCount() < threads()) {
      // grow with headroom (resizing forgets every slot's state)
      context.resize(static_cast<int>(std::min(agents, count + count / 2 + 8)), static_cast<int>(joints), threads());
      slots.assign(static_cast<std::size_t>(context.characterCount()), -1);
    }
    if (slots.size() != static_cast<std::size_t>(context.characterCount())) // forgotten (setAgents() and the like)
      slots.assign(static_cast<std::size_t>(context.characterCount()), -1);
    for (std::size_t k = 0; k < count; ++k)
      if (slots[k] != list[k]) { // another agent in this slot: the keys and cursors it holds are not this one's
        context.reset(static_cast<int>(k));
        slots[k] = list[k];
      }
    m_clips.assign(count, &level.clip);
    m_times.resize(count);
    for (std::size_t k = 0; k < count; ++k) {
      const double t = seconds + m_agents[static_cast<std::size_t>(list[k])].timeOffset;
      m_times[k] = std::isfinite(t) && t > 0.0 ? t : 0.0;
    }
    m_palettes[li].resize(count * joints);
    m_models[li].resize(m_writeModels ? count * joints : 0);
    PoseEvaluatorJob job;
    job.parents = level.parents;
    job.inverseBinds = level.inverseBinds;
    job.clips = m_clips;
    job.times = m_times;
    job.context = &context;
    job.pool = m_pool.get();
    job.blendFrames = m_blendFrames;
    job.out_models = m_models[li];
    job.out_palette = m_palettes[li];
    if (!job.run())
      return Error("crowd: the pose evaluator refused level " + std::to_string(l) + "'s inputs");
    m_stats.jointsEvaluated += context.jointsSampled();
  }
  m_stats.poseCpuMs = 1000.0 * (threadCpuSeconds() - cpuStart);
  const auto posed = std::chrono::steady_clock::now();
  m_stats.poseMs = std::chrono::duration<double, std::milli>(posed - wallStart).count();
  m_stats.skinMs = 0.0;
  if (m_skin) {
    for (int l = 0; l < levels; ++l) {
      const std::size_t li = static_cast<std::size_t>(l);
      SkinTask task{&*m_skinning[li], m_palettes[li].data(), m_levels[li].parents.size(), this};
      const int count = static_cast<int>(m_levelAgents[li].size());
      if (count == 0)
        continue;
      if (m_pool)
        m_pool->run(count, std::max(1, count / (threads() * 8)), &Crowd::skinAgents, &task);
      else
        skinAgents(&task, 0, count, 0);
      if (task.failed)
        return Error("crowd: the skinning job refused level " + std::to_string(l) + "'s inputs");
    }
    m_stats.skinMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - posed).count();
  }
  return {};
}

void Crowd::skinAgents(void* data, int begin, int end, int thread) {
  SkinTask& task = *static_cast<SkinTask*>(data);
  const std::size_t t = static_cast<std::size_t>(thread);
  const std::size_t vertices = static_cast<std::size_t>(task.mesh->vertexCount());
  const std::span<glm::vec3> positions(task.crowd->m_skinPositions[t].data(), vertices);
  const std::span<glm::vec3> normals(task.crowd->m_skinNormals[t].data(), task.mesh->hasNormals() ? vertices : 0);
  for (int k = begin; k < end; ++k)
    if (!task.mesh->skin(std::span<const glm::mat4>(task.palettes + static_cast<std::size_t>(k) * task.joints, task.joints),
                         positions, normals))
      task.failed = true;
}

glm::vec3 crowdFrontCamera(std::span<const CrowdAgent> agents) {
  if (agents.empty())
    return glm::vec3(0.0f, 170.0f, -1000.0f);
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const CrowdAgent& agent : agents) {
    lo = glm::min(lo, agent.position);
    hi = glm::max(hi, agent.position + glm::vec3(0.0f, 180.0f, 0.0f));
  }
  // the dock's orbit camera: target 6 m inside the front row, 9 m away, pitched 0.3 rad
  // down, looking along +Z
  const float pitch = -0.3f, distance = 900.0f;
  const glm::vec3 target(0.5f * (lo.x + hi.x), 0.0f, lo.z + 600.0f);
  const glm::vec3 forward(0.0f, std::sin(pitch), std::cos(pitch));
  return target - distance * forward;
}

namespace {

CrowdComparison::Spread spreadOf(std::vector<double> values) {
  CrowdComparison::Spread out;
  if (values.empty())
    return out;
  std::sort(values.begin(), values.end());
  const std::size_t mid = values.size() / 2;
  out.median = values.size() % 2 ? values[mid] : 0.5 * (values[mid - 1] + values[mid]);
  out.min = values.front();
  out.max = values.back();
  out.samples = static_cast<int>(values.size());
  return out;
}

double median(std::vector<double> values) { return spreadOf(std::move(values)).median; }

bool hasOverrideAt(const JpcSettings& jpc, std::size_t level) {
  for (const auto& [name, joint] : jpc.joints)
    if (level < joint.thresholds.size() && joint.thresholds[level])
      return true;
  return false;
}

// CrowdConfigurationFigures::clipBytes: the clips of the levels used, one per motion.
std::size_t usedClipBytes(const Crowd& crowd, const LodSet& set, const JpcSettings& jpc,
                          const std::vector<bool>& used) {
  std::size_t bytes = 0;
  std::vector<double> counted; // thresholds of the override-free levels counted
  for (int l = 0; l < crowd.levelCount(); ++l) {
    const std::size_t level = static_cast<std::size_t>(l);
    if (level >= used.size() || !used[level])
      continue;
    const double threshold = level < set.levels.size() ? set.levels[level].motionThreshold : -1.0;
    if (!hasOverrideAt(jpc, level)) {
      if (std::find(counted.begin(), counted.end(), threshold) != counted.end())
        continue;
      counted.push_back(threshold);
    }
    bytes += crowd.level(l).clip.byteSize();
  }
  return bytes;
}

} // namespace

CrowdComparison::Spread CrowdComparison::frameMsSpread(int i) const {
  return spreadOf(configurations[i].repetitionFrameMs);
}

CrowdComparison::Spread CrowdComparison::speedupSpread(int i) const {
  const std::vector<double>& none = configurations[0].repetitionFrameMs;
  const std::vector<double>& other = configurations[i].repetitionFrameMs;
  std::vector<double> ratios;
  for (std::size_t r = 0; r < none.size() && r < other.size(); ++r)
    if (other[r] > 0.0)
      ratios.push_back(none[r] / other[r]);
  return spreadOf(std::move(ratios));
}

Result<CrowdComparison> compareCrowdConfigurations(const Skeleton& skeleton, const SkinnedMesh* mesh, const Clip& clip,
                                                   const LodSet& lods, std::span<const CrowdAgent> agents,
                                                   const glm::vec3& camera, const CrowdComparisonSettings& settings) {
  // the four configurations' LOD sets: the same levels and switch distances; skeletal keeps
  // every mesh whole, mesh keeps the original motion (threshold 0)
  LodSet skeletalSet = lods, meshSet = lods;
  for (std::size_t i = 1; i < lods.levels.size(); ++i) {
    skeletalSet.levels[i].meshRatio = 1.0;
    meshSet.levels[i].motionThreshold = 0.0;
  }
  const LodSet* sets[4] = {&lods, &skeletalSet, &meshSet, &lods}; // none: level 0 of "both" alone
  static const char* const kNames[4] = {"none", "skeletal", "mesh", "both"};
  Crowd crowds[4];
  CrowdComparison out;
  const std::vector<CrowdAgent> placed(agents.begin(), agents.end());
  for (int c = 3; c >= 1; --c) {
    Result<std::vector<CrowdLevel>> levels = buildCrowdLevels(skeleton, mesh, clip, *sets[c], settings.jpc, settings.cancel);
    if (!levels)
      return levels.error();
    if (c == 3) { // none plays level 0 of these everywhere
      for (const CrowdLevel& level : *levels)
        out.levels.push_back({level.mesh.triangleCount(), level.mesh.vertexCount(), level.skeleton.jointCount()});
      crowds[0].setLevels(*levels);
    }
    crowds[c].setLevels(std::move(levels).value());
  }
  for (int c = 0; c < 4; ++c) {
    Crowd& crowd = crowds[c];
    out.configurations[c].name = kNames[c];
    crowd.setSwitches(lodSwitchesByDistance(lods), lodSwitchesByScreenSize(lods));
    crowd.setCentreHeight(settings.centreHeightCm);
    crowd.setThreads(settings.threads);
    crowd.setSkinning(settings.skinning);
    Crowd::Selection selection;
    selection.forcedLevel = c == 0 ? 0 : -1;
    crowd.setSelection(selection);
  }
  const int frames = std::max(settings.frames, 1);
  std::vector<double> poseMs[4], skinMs[4];
  std::vector<bool> used[4]; // per configuration, the levels an agent stood at in a timed frame
  // one warm-up each, then the repetitions, alternating the configurations
  for (int r = -1; r < std::max(settings.repetitions, 1); ++r)
    for (int c = 0; c < 4; ++c) {
      if (settings.cancel && settings.cancel->load())
        return Error("cancelled");
      Crowd& crowd = crowds[c];
      crowd.setAgents(placed); // the same start every repetition: no level kept from the last
      double pose = 0.0, skin = 0.0, joints = 0.0, vertices = 0.0;
      for (int frame = 0; frame < frames; ++frame) {
        if (Error error = crowd.update(settings.startSeconds + frame * settings.frameSeconds, camera))
          return error;
        const CrowdFrameStats& stats = crowd.stats();
        pose += stats.poseMs;
        skin += stats.skinMs;
        joints += static_cast<double>(stats.jointsEvaluated);
        vertices += static_cast<double>(stats.verticesSkinned);
        if (r >= 0) {
          used[c].resize(stats.agentsPerLevel.size());
          for (std::size_t l = 0; l < stats.agentsPerLevel.size(); ++l)
            used[c][l] = used[c][l] || stats.agentsPerLevel[l] > 0;
        }
      }
      if (r < 0)
        continue;
      CrowdConfigurationFigures& figures = out.configurations[c];
      poseMs[c].push_back(pose / frames);
      skinMs[c].push_back(skin / frames);
      figures.repetitionFrameMs.push_back((pose + skin) / frames);
      figures.jointsEvaluated = joints / frames;
      figures.verticesSkinned = vertices / frames;
      figures.agentsPerLevel = crowd.stats().agentsPerLevel;
    }
  for (int c = 0; c < 4; ++c) {
    CrowdConfigurationFigures& figures = out.configurations[c];
    figures.poseMs = median(poseMs[c]);
    figures.skinMs = median(skinMs[c]);
    figures.frameMs = median(figures.repetitionFrameMs);
    figures.clipBytes = usedClipBytes(crowds[c], *sets[c], settings.jpc, used[c]);
  }
  out.clipSeconds = crowds[3].level(0).clip.duration();
  if (settings.levelCosts) {
    // every agent at level k in turn, on the crowd of "both": the levels alternate within a
    // repetition, so each repetition's levels share the machine's load
    Crowd& crowd = crowds[3];
    const int levelCount = crowd.levelCount();
    std::vector<std::vector<double>> frameMs(static_cast<std::size_t>(levelCount));
    for (int r = -1; r < std::max(settings.repetitions, 1); ++r)
      for (int k = 0; k < levelCount; ++k) {
        if (settings.cancel && settings.cancel->load())
          return Error("cancelled");
        Crowd::Selection selection;
        selection.forcedLevel = k;
        crowd.setSelection(selection);
        crowd.setAgents(placed);
        double ms = 0.0;
        for (int frame = 0; frame < frames; ++frame) {
          if (Error error = crowd.update(settings.startSeconds + frame * settings.frameSeconds, camera))
            return error;
          ms += crowd.stats().poseMs + crowd.stats().skinMs;
        }
        if (r >= 0)
          frameMs[static_cast<std::size_t>(k)].push_back(ms / frames);
      }
    for (const std::vector<double>& times : frameMs)
      out.levelFrameMs.push_back(median(times));
    for (double ms : out.levelFrameMs)
      out.levelCost.push_back(out.levelFrameMs[0] > 0.0 ? ms / out.levelFrameMs[0] : 0.0);
  }
  return out;
}

SkinnedMesh boneCapsuleMesh(const Skeleton& skeleton, float radiusCm) {
  SkinnedMesh mesh;
  mesh.name = "bone capsules";
  const std::vector<glm::mat4> rest = skeleton.restModelMatrices();
  constexpr int kSides = 6;
  // One capsule: a hexagonal prism from a to b with pyramid caps, bound to `joint`.
  auto addCapsule = [&](const glm::vec3& a, const glm::vec3& b, float radius, int joint) {
    glm::vec3 axis = b - a;
    const float length = glm::length(axis);
    axis = length > 0.0f ? axis / length : glm::vec3(0.0f, 1.0f, 0.0f);
    const glm::vec3 helper = std::abs(axis.y) < 0.9f ? glm::vec3(0.0f, 1.0f, 0.0f) : glm::vec3(1.0f, 0.0f, 0.0f);
    const glm::vec3 u = glm::normalize(glm::cross(axis, helper));
    const glm::vec3 v = glm::cross(axis, u);
    const float cap = std::min(radius, 0.5f * length);
    const glm::vec3 a1 = a + axis * cap, b1 = b - axis * cap;
    const std::uint32_t base = static_cast<std::uint32_t>(mesh.positions.size());
    auto push = [&](const glm::vec3& p, const glm::vec3& n) {
      mesh.positions.push_back(p);
      mesh.normals.push_back(n);
      mesh.joints.emplace_back(static_cast<std::uint16_t>(joint), 0, 0, 0);
      mesh.weights.emplace_back(1.0f, 0.0f, 0.0f, 0.0f);
    };
    push(a, -axis); // base + 0
    push(b, axis);  // base + 1
    for (int s = 0; s < kSides; ++s) {
      const float angle = glm::two_pi<float>() * static_cast<float>(s) / kSides;
      const glm::vec3 n = std::cos(angle) * u + std::sin(angle) * v;
      push(a1 + radius * n, n); // base + 2 + 2s
      push(b1 + radius * n, n); // base + 3 + 2s
    }
    for (int s = 0; s < kSides; ++s) {
      const std::uint32_t i0 = base + 2 + 2 * static_cast<std::uint32_t>(s);
      const std::uint32_t i1 = base + 2 + 2 * static_cast<std::uint32_t>((s + 1) % kSides);
      const std::uint32_t tri[] = {i0, i1, i0 + 1, i1, i1 + 1, i0 + 1, base, i1, i0, base + 1, i0 + 1, i1 + 1};
      mesh.indices.insert(mesh.indices.end(), std::begin(tri), std::end(tri));
    }
  };
  for (int j = 1; j < skeleton.jointCount(); ++j) {
    const int parent = skeleton.joints[static_cast<std::size_t>(j)].parent;
    const glm::vec3 a(rest[static_cast<std::size_t>(parent)][3]), b(rest[static_cast<std::size_t>(j)][3]);
    const float length = glm::length(b - a);
    if (length < 1e-3f)
      continue;
    addCapsule(a, b, std::min(radiusCm, 0.2f * length), parent);
  }
  if (mesh.positions.empty() && !skeleton.empty()) {
    const glm::vec3 root(rest.front()[3]);
    addCapsule(root - glm::vec3(0.0f, radiusCm, 0.0f), root + glm::vec3(0.0f, radiusCm, 0.0f), radiusCm, 0);
  }
  return mesh;
}

} // namespace mlod
