// Runtime LOD speed (issues 4, 13): core's crowd loop (the pose evaluator through Crowd, as
// `motionlod bench-crowd` and the Crowd dock run it) at full detail and at the LOD of the
// paper's thresholds on CMU 01_01 (5.6444 cm per unit, alpha 5), and skinning of
// BCN_Epileptic. One iteration = one frame of the whole crowd; items = character-frames
// (or vertices for skinning).
//   bench_crowd --benchmark_filter=Pose
// Figures go in the issue note; nothing here asserts a time. `motionlod bench-crowd` runs
// full detail and LOD alternately in one process, which is the comparison to quote.

#include "core/crowd/crowd.h"
#include "core/jpc/jpc.h"
#include "core/lod_clip_builder.h"
#include "io/importer.h"
#include "runtime/pose_evaluator.h"
#include "runtime/skinning_job.h"

#include <benchmark/benchmark.h>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

namespace mlod {
namespace {

constexpr int kCharacters = 256;

const Asset& asset(const std::string& relative) {
  static std::map<std::string, Asset> cache;
  auto found = cache.find(relative);
  if (found == cache.end()) {
    ImportOptions options;
    if (relative.find("BVH/") == 0)
      options.unitScale = 5.6444;
    Result<Asset> imported = importAsset(std::string(MLOD_ASSIMP_MODELS) + "/" + relative, options);
    if (!imported)
      throw std::runtime_error(imported.message());
    found = cache.emplace(relative, std::move(imported).value()).first;
  }
  return found->second;
}

// The crowd level of CMU 01_01 at `threshold` (< 0: full detail, no clusters): the original
// skeleton, no bone removed, the clip looping.
const CrowdLevel& cmuLevel(double threshold) {
  static std::map<double, CrowdLevel> cache;
  auto found = cache.find(threshold);
  if (found == cache.end()) {
    const Asset& cmu = asset("BVH/01_01.bvh");
    ClusterSet clusters;
    if (threshold >= 0.0) {
      JpcSettings settings;
      settings.zeroLength = 1e-6 * cmu.unitScale;
      const double thresholds[1] = {threshold};
      Result<std::vector<JpcLevelResult>> levels = simplifyClip(cmu.skeleton, cmu.clips.front(), settings, thresholds);
      if (!levels)
        throw std::runtime_error(levels.message());
      clusters = levels->front().clusters;
    }
    Result<CrowdLevel> built =
        buildCrowdLevel(cmu.skeleton, nullptr, cmu.clips.front(), threshold >= 0.0 ? &clusters : nullptr);
    if (!built)
      throw std::runtime_error(built.message());
    found = cache.emplace(threshold, std::move(built).value()).first;
  }
  return found->second;
}

// Args: threshold (-1 = full detail), blend frames, 1 = model matrices and palette / 0 = palette only.
// The crowd loop of core's Crowd (one level, every agent at it), as `motionlod bench-crowd`
// and the studio's Crowd dock run it.
void BM_Pose(benchmark::State& state) {
  const double threshold = static_cast<double>(state.range(0));
  Crowd crowd;
  crowd.setLevels({cmuLevel(threshold)});
  Crowd::Selection selection;
  selection.forcedLevel = 0;
  crowd.setSelection(selection);
  crowd.setBlendFrames(static_cast<int>(state.range(1)));
  crowd.setModels(state.range(2) != 0);
  std::vector<CrowdAgent> agents(kCharacters);
  const double duration = crowd.level(0).clip.duration();
  for (int c = 0; c < kCharacters; ++c)
    agents[static_cast<std::size_t>(c)].timeOffset = std::fmod(c * 0.6180339887498949, 1.0) * duration;
  crowd.setAgents(agents);
  std::int64_t frame = 0, sampled = 0;
  for (auto _ : state) {
    if (Error error = crowd.update(static_cast<double>(frame++) / 60.0, glm::vec3(0.0f)))
      state.SkipWithError(error.message().c_str());
    sampled += crowd.stats().jointsEvaluated;
    benchmark::DoNotOptimize(crowd.levelPalettes(0).data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * kCharacters);
  state.counters["joints_sampled_per_cf"] =
      static_cast<double>(sampled) / static_cast<double>(std::max<std::int64_t>(1, state.iterations() * kCharacters));
}
BENCHMARK(BM_Pose)
    ->ArgNames({"E", "blend", "models"})
    ->ArgsProduct({{-1, 5, 50, 100, 300}, {0, 4}, {1, 0}})
    ->Unit(benchmark::kMicrosecond);

// BCN_Epileptic's mesh skinned with its clip's palette: items = vertices.
void BM_Skinning(benchmark::State& state) {
  const Asset& character = asset("X/BCN_Epileptic.X");
  const SkinnedMesh* mesh = nullptr;
  for (const SkinnedMesh& m : character.meshes)
    if (m.skinned() && !mesh)
      mesh = &m;
  Result<SkinningMesh> skinning = buildSkinningMesh(*mesh, character.skeleton.jointCount());
  Result<LodClip> clip = buildLodClip(character.clips.front());
  if (!skinning || !clip) {
    state.SkipWithError("BCN_Epileptic did not build");
    return;
  }
  const std::vector<std::int16_t> parents = character.skeleton.parentIndices();
  const std::vector<glm::mat4> inverseBinds = paletteInverseBinds(character.skeleton);
  std::vector<glm::mat4> palette(parents.size());
  PoseEvaluatorContext context(1, static_cast<int>(parents.size()));
  const LodClip* clips[1] = {&*clip};
  const double time = 0.5 * clip->duration();
  PoseEvaluatorJob job;
  job.parents = parents;
  job.inverseBinds = inverseBinds;
  job.clips = clips;
  job.times = std::span<const double>(&time, 1);
  job.context = &context;
  job.out_palette = palette;
  if (!job.run()) {
    state.SkipWithError("the pose job did not validate");
    return;
  }
  const std::size_t vertices = static_cast<std::size_t>(skinning->vertexCount());
  std::vector<glm::vec3> positions(vertices), normals(skinning->hasNormals() ? vertices : 0);
  for (auto _ : state) {
    if (!skinning->skin(palette, positions, normals))
      state.SkipWithError("the skinning job did not validate");
    benchmark::DoNotOptimize(positions.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(vertices));
}
BENCHMARK(BM_Skinning)->Unit(benchmark::kMicrosecond);

} // namespace
} // namespace mlod

BENCHMARK_MAIN();
