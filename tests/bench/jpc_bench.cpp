// JPC speed (issue 3): the error kernel, one joint's clustering (re-clustering after an
// edit), the whole skeleton. Real CMU clips at 5.6444 cm per unit, alpha 5.
//   bench_jpc --benchmark_filter=Kernel
// Figures go in the issue note; nothing here asserts a time.

#include "core/jpc/clustering_table.h"
#include "core/jpc/jpc.h"
#include "core/jpc/key_posture.h"
#include "io/importer.h"

#include <benchmark/benchmark.h>
#include <chrono>
#include <map>
#include <stdexcept>
#include <string>

namespace mlod {
namespace {

const Asset& cmuAsset(const std::string& name) {
  static std::map<std::string, Asset> cache;
  auto found = cache.find(name);
  if (found == cache.end()) {
    ImportOptions options;
    options.unitScale = 5.6444;
    Result<Asset> asset = importAsset(std::string(MLOD_ASSIMP_MODELS) + "/BVH/" + name, options);
    if (!asset)
      throw std::runtime_error(asset.message());
    found = cache.emplace(name, std::move(asset).value()).first;
  }
  return found->second;
}

JpcSettings settingsFor(JpcMode mode) {
  JpcSettings settings;
  settings.alpha = 5.0;
  settings.mode = mode;
  settings.zeroLength = 1e-6 * 5.6444;
  return settings;
}

const JpcClip& prepared(const std::string& file, JpcMode mode) {
  static std::map<std::pair<std::string, JpcMode>, JpcClip> cache;
  auto found = cache.find({file, mode});
  if (found == cache.end()) {
    const Asset& asset = cmuAsset(file);
    found = cache
                .emplace(std::make_pair(file, mode),
                         *JpcClip::prepare(asset.skeleton, asset.clips.front(), settingsFor(mode)))
                .first;
  }
  return found->second;
}

int jointIndex(const std::string& file, const char* name) {
  return cmuAsset(file).skeleton.find(name);
}

// Scalar double kernel, eq. (1): a row of the table at a time.
void BM_ErrorKernelExact(benchmark::State& state, const char* joint) {
  const JointTrack& track = prepared("01_01.bvh", JpcMode::Greedy).track(jointIndex("01_01.bvh", joint));
  const int n = track.frameCount();
  int ref = 0;
  for (auto _ : state) {
    double sum = 0.0;
    for (int t = 0; t < n; ++t)
      sum += track.error(t, ref);
    benchmark::DoNotOptimize(sum);
    ref = (ref + 97) % n;
  }
  state.SetItemsProcessed(state.iterations() * n);
}

// Float SIMD approximation (AVX2 where available), the same rows.
void BM_ErrorKernelApproximate(benchmark::State& state, const char* joint) {
  const JointTrack& track = prepared("01_01.bvh", JpcMode::Greedy).track(jointIndex("01_01.bvh", joint));
  const int n = track.frameCount();
  std::vector<float> row(static_cast<std::size_t>(n));
  int ref = 0;
  for (auto _ : state) {
    track.approximateErrors(ref, 0, n, row.data());
    benchmark::DoNotOptimize(row.data());
    ref = (ref + 97) % n;
  }
  state.SetItemsProcessed(state.iterations() * n);
}
BENCHMARK_CAPTURE(BM_ErrorKernelExact, Hips_3_directions, "Hips");
BENCHMARK_CAPTURE(BM_ErrorKernelExact, Head_1_direction, "Head");
BENCHMARK_CAPTURE(BM_ErrorKernelApproximate, Hips_3_directions, "Hips");
BENCHMARK_CAPTURE(BM_ErrorKernelApproximate, Head_1_direction, "Head");

// One joint's clustering on 01_01.bvh (2,752 frames): what re-clustering after an edit of
// its threshold costs. Args: threshold.
void BM_ClusterJoint(benchmark::State& state, const char* joint, JpcMode mode) {
  const JointTrack& track = prepared("01_01.bvh", mode).track(jointIndex("01_01.bvh", joint));
  const double threshold = static_cast<double>(state.range(0));
  std::int64_t evaluations = 0;
  for (auto _ : state) {
    const JointClustering result = clusterJoint(track, threshold, mode);
    evaluations = result.evaluations;
    benchmark::DoNotOptimize(result.clusters.data());
  }
  state.counters["exact_evaluations"] = static_cast<double>(evaluations);
}
BENCHMARK_CAPTURE(BM_ClusterJoint, Head_greedy, "Head", JpcMode::Greedy)
    ->Arg(5)
    ->Arg(50)
    ->Arg(300)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ClusterJoint, Head_optimal, "Head", JpcMode::Optimal)
    ->Arg(5)
    ->Arg(50)
    ->Arg(300)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ClusterJoint, Hips_greedy, "Hips", JpcMode::Greedy)
    ->Arg(5)
    ->Arg(50)
    ->Arg(300)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ClusterJoint, RThumb_greedy, "RThumb", JpcMode::Greedy)
    ->Arg(5)
    ->Arg(50)
    ->Arg(300)
    ->Unit(benchmark::kMillisecond);

// The slowest joint of 01_01 at each threshold, greedy: the worst case of an edit.
void BM_ClusterJointSlowest(benchmark::State& state) {
  const JpcClip& clip = prepared("01_01.bvh", JpcMode::Greedy);
  const double threshold = static_cast<double>(state.range(0));
  int slowest = -1;
  double slowestSeconds = -1.0;
  for (int j = 0; j < clip.jointCount(); ++j) {
    if (!clip.clusterable(j))
      continue;
    const auto start = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(clusterJoint(clip.track(j), threshold, JpcMode::Greedy).clusters.data());
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (seconds > slowestSeconds) {
      slowestSeconds = seconds;
      slowest = j;
    }
  }
  state.SetLabel(clip.jointName(slowest));
  for (auto _ : state)
    benchmark::DoNotOptimize(clusterJoint(clip.track(slowest), threshold, JpcMode::Greedy).clusters.data());
}
BENCHMARK(BM_ClusterJointSlowest)->Arg(0)->Arg(5)->Arg(50)->Arg(100)->Arg(300)->Unit(benchmark::kMillisecond);

// The whole skeleton of 01_03.bvh (4,511 frames, 31 clusterable joints): clustering,
// metrics and forward kinematics, as `motionlod simplify` runs it. Args: threads (0 = all).
void BM_SimplifyClip(benchmark::State& state, JpcMode mode, std::vector<double> thresholds) {
  const Asset& asset = cmuAsset("01_03.bvh");
  const int threads = static_cast<int>(state.range(0));
  for (auto _ : state) {
    Result<std::vector<JpcLevelResult>> result =
        simplifyClip(asset.skeleton, asset.clips.front(), settingsFor(mode), thresholds, threads);
    benchmark::DoNotOptimize(result.ok());
  }
}
BENCHMARK_CAPTURE(BM_SimplifyClip, greedy_T300, JpcMode::Greedy, std::vector<double>{300.0})
    ->Arg(1)
    ->Arg(0)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_SimplifyClip, greedy_T0_5_50_100_300, JpcMode::Greedy, std::vector<double>{0, 5, 50, 100, 300})
    ->Arg(1)
    ->Arg(0)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_SimplifyClip, optimal_T0_5_50_100_300, JpcMode::Optimal, std::vector<double>{0, 5, 50, 100, 300})
    ->Arg(1)
    ->Arg(0)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Preparing a clip (tracks, child directions): once per clip or alpha edit.
void BM_PrepareClip(benchmark::State& state) {
  const Asset& asset = cmuAsset("01_03.bvh");
  for (auto _ : state)
    benchmark::DoNotOptimize(JpcClip::prepare(asset.skeleton, asset.clips.front(), settingsFor(JpcMode::Greedy)).ok());
}
BENCHMARK(BM_PrepareClip)->Unit(benchmark::kMillisecond);

} // namespace
} // namespace mlod

BENCHMARK_MAIN();
