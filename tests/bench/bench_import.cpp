// Import speed on real files: in-process, and through the sandboxed worker the CLI and
// the studio use (fork, import, send the asset through a pipe, rebuild it).
//   build/bin/bench_import --benchmark_min_time=2

#include "io/importer.h"
#include "io/isolated_import.h"

#include <benchmark/benchmark.h>

#include <string>

namespace {

std::string model(const char* relative) { return std::string(MLOD_ASSIMP_MODELS) + "/" + relative; }

void importInProcess(benchmark::State& state, const char* file) {
  const std::string path = model(file);
  for (auto _ : state) {
    mlod::Result<mlod::Asset> asset = mlod::importAsset(path);
    if (!asset)
      state.SkipWithError(asset.message().c_str());
    benchmark::DoNotOptimize(asset);
  }
}

void importIsolated(benchmark::State& state, const char* file) {
  const std::string path = model(file);
  for (auto _ : state) {
    mlod::Result<mlod::Asset> asset = mlod::importAssetIsolated(path);
    if (!asset)
      state.SkipWithError(asset.message().c_str());
    benchmark::DoNotOptimize(asset);
  }
}

BENCHMARK_CAPTURE(importInProcess, cmu_01_01_bvh, "BVH/01_01.bvh")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(importIsolated, cmu_01_01_bvh, "BVH/01_01.bvh")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(importInProcess, cmu_01_03_bvh, "BVH/01_03.bvh")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(importInProcess, bcn_epileptic_x, "X/BCN_Epileptic.X")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(importIsolated, bcn_epileptic_x, "X/BCN_Epileptic.X")->Unit(benchmark::kMillisecond);

} // namespace

BENCHMARK_MAIN();
