// The pixel budget's level search (issue 26, item 4): LodSet::fromPixelBudget as the
// studio's Budget dialog preview runs it (editor/document/level_generator.h: the asset's
// own clips plus the motion mapped onto it, default JPC and mesh settings) on skinned
// characters of Debian's assimp-testmodels playing the 4,511-frame CMU clip 01_03, 1 pixel,
// 4 levels. One iteration = one whole generation.
//   bench_budget --benchmark_filter=PixelBudget
// Figures go in the issue note; nothing here asserts a time.

#include "core/lod/lod_set.h"
#include "core/mapping/motion_mapping.h"
#include "io/importer.h"

#include <benchmark/benchmark.h>
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

BENCHMARK_CAPTURE(BM_PixelBudget, BCN_Epileptic_4, "X/BCN_Epileptic.X", 4)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);
BENCHMARK_CAPTURE(BM_PixelBudget, Testwuson_4, "X/Testwuson.X", 4)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

} // namespace
} // namespace mlod

BENCHMARK_MAIN();
