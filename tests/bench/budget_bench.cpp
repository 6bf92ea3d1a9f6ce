// The pixel budget's level search (issue 26, item 4): LodSet::fromPixelBudget as the
// studio's Budget dialog preview runs it (editor/document/level_generator.h: the asset's
// own clips plus the motion mapped onto it, default JPC and mesh settings) on skinned
// characters of Debian's assimp-testmodels playing the 4,511-frame CMU clip 01_03, 1 pixel,
// 4 levels. One iteration = one whole generation.
//   bench_budget --benchmark_filter=PixelBudget
// Figures go in the issue note; nothing here asserts a time.
//   bench_budget --print-levels
// prints every field of the levels (17 significant digits) of both characters at (levels,
// px) = (4, 1), (5, 1), (4, 2), (3, 0.5), (6, 4): compare before and after a change that must
// leave the budget's result as it was. `--print-levels cached` runs them one after another
// with one LodBudgetCache per character (lod_budget_cache.h): the same lines.

#include "core/lod/lod_set.h"
#include "core/mapping/motion_mapping.h"
#include "io/importer.h"

#include <benchmark/benchmark.h>
#include <cstdio>
#include <cstring>
#include <map>
#include <stdexcept>
#include <string>

namespace mlod {
namespace {

const Asset& imported(const std::string& relative) {
  static std::map<std::string, Asset> cache;
  auto found = cache.find(relative);
  if (found == cache.end()) {
    Result<Asset> asset = importAsset(std::string(MLOD_ASSIMP_MODELS) + "/" + relative); // the file's or a guessed unit
    if (!asset)
      throw std::runtime_error(relative + ": " + asset.message());
    found = cache.emplace(relative, std::move(asset).value()).first;
  }
  return found->second;
}

// The character's clips and the motion's first clip mapped onto it, as the studio plays them.
std::vector<Clip> mappedClips(const std::string& character, const std::string& motion) {
  const Asset& target = imported(character);
  const Asset& source = imported(motion);
  Result<MappedMotion> mapped =
      mapMotionAutomatically(source.skeleton, std::span<const Clip>(source.clips).first(1), target.skeleton, character);
  if (!mapped)
    throw std::runtime_error(motion + " on " + character + ": " + mapped.message());
  return std::move(mapped->clips);
}

void BM_PixelBudget(benchmark::State& state, const char* character, int levels) {
  const Asset& asset = imported(character);
  const std::vector<Clip> clips = mappedClips(character, "BVH/01_03.bvh");
  LodBudgetOptions options;
  options.clips = clips;
  options.jpc.zeroLength = 1e-6 * asset.unitScale;
  std::size_t kept = 0;
  for (auto _ : state) {
    Result<LodSet> set = LodSet::fromPixelBudget(asset, 1.0, levels, options);
    if (!set) {
      state.SkipWithError(set.message().c_str());
      return;
    }
    kept = set->levels.size();
    benchmark::DoNotOptimize(set->levels.data());
  }
  int frames = 0;
  for (const Clip& clip : asset.clips)
    frames += clip.frameCount;
  for (const Clip& clip : clips)
    frames += clip.frameCount;
  state.counters["frames"] = frames;
  state.counters["levels_kept"] = double(kept);
}

// Options of a search through `cache` for `asset` playing `clips`, and that search run once at
// 1 px (untimed: what the benchmarks after it reuse); false, the benchmark skipped, if it fails.
bool searchedOnce(benchmark::State& state, const Asset& asset, const std::vector<Clip>& clips, int levels,
                  LodBudgetCache& cache, LodBudgetOptions& options) {
  options.clips = clips;
  options.jpc.zeroLength = 1e-6 * asset.unitScale;
  options.cache = &cache;
  if (Result<LodSet> first = LodSet::fromPixelBudget(asset, 1.0, levels, options); !first) {
    state.SkipWithError(first.message().c_str());
    return false;
  }
  return true;
}

// The Budget preview asked again for the same character (another pixel budget, 2 px: the
// motions and meshes of the first run reused, lod_budget_cache.h): the first run at 1 px
// is not timed.
void BM_PixelBudgetAgain(benchmark::State& state, const char* character, int levels) {
  const Asset& asset = imported(character);
  const std::vector<Clip> clips = mappedClips(character, "BVH/01_03.bvh");
  LodBudgetCache cache;
  LodBudgetOptions options;
  if (!searchedOnce(state, asset, clips, levels, cache, options))
    return;
  LodBudgetReport report;
  for (auto _ : state) {
    Result<LodSet> set = LodSet::fromPixelBudget(asset, 2.0, levels, options, &report);
    if (!set) {
      state.SkipWithError(set.message().c_str());
      return;
    }
    benchmark::DoNotOptimize(set->levels.data());
  }
  state.counters["joints_clustered"] = report.jointsClustered;
  state.counters["meshes_built"] = report.meshesBuilt;
}

// The preview after an edit of one joint (the alpha of the root's first child): that joint
// is clustered again, the motions and meshes are made again (they depend on every joint).
void BM_PixelBudgetAfterJointEdit(benchmark::State& state, const char* character, int levels) {
  const Asset& asset = imported(character);
  const std::vector<Clip> clips = mappedClips(character, "BVH/01_03.bvh");
  LodBudgetCache cache;
  LodBudgetOptions options;
  if (!searchedOnce(state, asset, clips, levels, cache, options))
    return;
  options.jpc.joints[asset.skeleton.joints.at(1).name].alpha = 10.0;
  LodBudgetReport report;
  for (auto _ : state) {
    Result<LodSet> set = LodSet::fromPixelBudget(asset, 1.0, levels, options, &report);
    if (!set) {
      state.SkipWithError(set.message().c_str());
      return;
    }
    benchmark::DoNotOptimize(set->levels.data());
  }
  state.counters["joints_clustered"] = report.jointsClustered;
  state.counters["motions_made"] = report.motionsMade;
  state.counters["meshes_built"] = report.meshesBuilt;
}

BENCHMARK_CAPTURE(BM_PixelBudget, BCN_Epileptic_4, "X/BCN_Epileptic.X", 4)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);
BENCHMARK_CAPTURE(BM_PixelBudget, Testwuson_4, "X/Testwuson.X", 4)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

// Every field of every level, one line each, to 17 significant digits.
int printLevels(bool cached) {
  for (const char* character : {"X/BCN_Epileptic.X", "X/Testwuson.X"}) {
    LodBudgetCache cache;
    const Asset& asset = imported(character);
    const std::vector<Clip> clips = mappedClips(character, "BVH/01_03.bvh");
    LodBudgetOptions options;
    options.clips = clips;
    options.jpc.zeroLength = 1e-6 * asset.unitScale;
    options.cache = cached ? &cache : nullptr;
    for (const auto& [levels, pixels] : {std::pair{4, 1.0}, {5, 1.0}, {4, 2.0}, {3, 0.5}, {6, 4.0}}) {
      LodBudgetReport report;
      Result<LodSet> set = LodSet::fromPixelBudget(asset, pixels, levels, options, &report);
      if (!set) {
        std::printf("%s %d levels %g px: error: %s\n", character, levels, pixels, set.message().c_str());
        continue;
      }
      std::printf("%s %d levels %g px: radius %.17g share %.17g\n", character, levels, pixels, set->boundingRadiusCm,
                  report.motionShare);
      for (std::size_t i = 0; i < set->levels.size(); ++i) {
        const LodLevel& l = set->levels[i];
        std::printf("  %s E %.17g ratio %.17g distance %.17g px %.17g size %.17g motion %.17g mesh %.17g tris %d "
                    "joints %d simplified %.17g\n",
                    l.name.c_str(), l.motionThreshold, l.meshRatio, l.switchDistanceCm, l.pixelError,
                    l.screenSizePixels, l.motionErrorCm, l.meshErrorCm, l.triangles, l.activeJoints,
                    report.simplifiedPercent[i]);
      }
      for (const std::string& line : report.dropped)
        std::printf("  dropped: %s\n", line.c_str());
    }
  }
  return 0;
}

BENCHMARK_CAPTURE(BM_PixelBudgetAgain, BCN_Epileptic_4, "X/BCN_Epileptic.X", 4)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);
BENCHMARK_CAPTURE(BM_PixelBudgetAgain, Testwuson_4, "X/Testwuson.X", 4)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);
BENCHMARK_CAPTURE(BM_PixelBudgetAfterJointEdit, BCN_Epileptic_4, "X/BCN_Epileptic.X", 4)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

} // namespace
} // namespace mlod

int main(int argc, char** argv) {
  if ((argc == 2 || argc == 3) && std::strcmp(argv[1], "--print-levels") == 0)
    return mlod::printLevels(argc == 3 && std::strcmp(argv[2], "cached") == 0);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv))
    return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
