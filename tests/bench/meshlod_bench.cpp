// bench_meshlod: the mesh LOD (core/mesh: whole mesh welded by position, quadrics over the
// bind pose and K clip poses) against meshoptimizer 0.18's meshopt_simplify on the
// position-welded indices, on the same meshes, at the same target triangle counts, posed by
// the same skin and frames, measured by the same code (MeshLod::errorsOf: sampled symmetric
// max distance in the bind pose, and max and mean over animated frames that neither
// simplifier saw). Errors in cm and in % of the bind-pose bounding-box diagonal. Where
// meshopt stops short of the target (more than 5% above it), a second row gives ours at the
// count meshopt reached, so the two are also compared at equal counts.
//
// Before the timed benchmarks, a table per character at 50%, 25% and 10%. The characters:
// BCN_Epileptic, or the files given in MLOD_MESHLOD_FILES (space-separated paths) with an
// optional unit scale after a colon (path:100).
//
// Timed (one thread): the whole simplification (ProgressiveMesh::build, which serves every
// level) plus one level's extraction, on BCN_Epileptic and on a synthetic skinned tube of 5k
// and 50k triangles; meshopt_simplify on the same for reference.
//
// Notes: what each choice of core/mesh/progressive_mesh measured when it was made (animated
// max distance, % of the bind-pose diagonal, unless said otherwise):
//  - triangles weigh sqrt(area), border and seam edges their length (meshoptimizer's units),
//    not area: BCN_Epileptic at 50% 0.36 -> 0.31;
//  - costs per unit of that weight, not its sum: WusonSMD at 25% 2.10 -> 1.46 (bind pose);
//    BCN_Epileptic at 25% 1.02 -> 0.79;
//  - borderWeight 1, seamWeight 0.1 (meshoptimizer's 10 and 1 assume its error divides by the
//    edges' weight too), at 25% / 10%: WusonSMD 1.46/3.61 -> 1.34/1.94, holy_grailref
//    3.44/4.28 -> 2.63/4.28, BCN_Epileptic 0.79/1.69 -> 0.71/1.61, Testwuson 3.12/3.76 ->
//    1.97/3.42; 0.5 and 0.05 measure alike;
//  - the move term (0.01): WusonSMD at 25% 2.74 -> 2.10 (bind pose);
//  - attribute collapses rank with the clean ones in one queue instead of a second tier:
//    Testwuson at 10% 9.77 -> 5.90;
//  - the welded mesh on OpenMesh (issue 27) instead of hand-written adjacency: every figure
//    of BCN_Epileptic, Testwuson, holy_grailref, anim_test and animation_with_skeleton the
//    same; WusonSMD at 50/25/10% 0.95/1.34/1.94 -> 1.03/1.34/1.76 (its non-manifold vertices,
//    2 locked before, are 7 now: a closed fan touched by another triangle is one too); CPU
//    time of BM_OursLevel beside the previous binary on the same (shared, loaded) machine,
//    median of 3, four rounds: BCN_Epileptic 1.0-1.15x, tube5k 1.2-1.35x, tube50k 0.96-1.22x.
//  - non-manifold input split by fan (edges of exactly two triangles in opposite directions
//    join a vertex's triangles into a fan; one vertex per fan, the copies locked) instead of
//    where add_face refused a triangle: WusonSMD 7 -> 6 locked (its vertex 1815 is manifold;
//    refusals had split it after its neighbour 114, where two closed fans meet), figures the
//    same but WusonSMD at 50% 0.42 -> 0.41 (with the fold quadrics below);
//  - folds (two triangles back to back, normals within 8 degrees of opposite) get a border's
//    edge quadrics: WusonSMD at 50/25/10% 1.03/1.34/1.76 -> 0.41/0.73/1.76, Testwuson at 10%
//    3.42 -> 2.36, every other figure the same (also at 40/30/20/15/12%, except Testwuson at
//    20% and 15%: 1.97 -> 2.06, and WusonSMD, lower). WusonSMD's halves meet along its middle in a slit 3e-5 cm
//    wide, whose vertices the two sheets' planes let slide along it for free; at 50% the
//    OpenMesh change kept the pinch vertex 114 (locked now; before OpenMesh it collapsed,
//    114 -> 3, at step 791) and took the slit's vertex 1187 instead (1187 -> 114, step 826):
//    0.95 -> 1.03. Within 18 degrees (-0.95) the table is the same but Testwuson at 10% 3.15
//    and at 20% 1.97 -> 3.15 (its pixel-budget levels lose one); 26 degrees (-0.9) also
//    BCN_Epileptic at 25% 0.69; 37 and 60 degrees (-0.8, -0.5) raise BCN_Epileptic at 50%
//    0.31 -> 0.35; at -0.9, half the weight (0.5) or a seam's (0.1) raise Testwuson or
//    WusonSMD at 10% (3.93, 3.82).

#include "../unit/core/mesh_lod_fixtures.h"
#include "core/mesh/mesh_lod.h"
#include "core/mesh/progressive_mesh.h"
#include "io/importer.h"

#include <benchmark/benchmark.h>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <memory>
#include <meshoptimizer.h>
#include <sstream>

namespace {

using namespace mlod;

Asset importOrExit(const std::string& path, double unitScale) {
  ImportOptions options;
  if (unitScale > 0.0)
    options.unitScale = unitScale;
  Result<Asset> imported = importAsset(path, options);
  if (!imported) {
    std::fprintf(stderr, "%s: %s\n", path.c_str(), imported.message().c_str());
    std::exit(1);
  }
  return std::move(imported).value();
}

const Asset& bcn() {
  static const Asset asset = importOrExit(std::string(MLOD_ASSIMP_MODELS) + "/X/BCN_Epileptic.X", 100.0);
  return asset;
}

const SkinnedMesh* characterMesh(const Asset& asset) {
  for (const SkinnedMesh& mesh : asset.meshes)
    if (mesh.skinned())
      return &mesh;
  return asset.meshes.empty() ? nullptr : &asset.meshes.front();
}

// Per vertex: the lowest vertex at its position (position welding alone, as meshopt is fed).
std::vector<std::uint32_t> positionWeld(const SkinnedMesh& mesh) {
  std::vector<std::uint32_t> remap(mesh.vertexCount()), first(mesh.vertexCount(), ~0u), weld(mesh.vertexCount());
  meshopt_generateVertexRemap(remap.data(), nullptr, mesh.vertexCount(), &mesh.positions[0].x, mesh.vertexCount(),
                              sizeof(glm::vec3));
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    if (first[remap[v]] == ~0u)
      first[remap[v]] = std::uint32_t(v);
    weld[v] = first[remap[v]];
  }
  return weld;
}

// meshopt_simplify on the position-welded indices (every corner replaced by the lowest vertex
// at its position), to `target` triangles; the result in original vertex indices.
MeshLevelIndices meshoptLevel(const SkinnedMesh& mesh, const std::vector<std::uint32_t>& weld, std::size_t target) {
  std::vector<std::uint32_t> welded(mesh.indices.size());
  for (std::size_t i = 0; i < welded.size(); ++i)
    welded[i] = weld[mesh.indices[i]];
  std::vector<std::uint32_t> destination(welded.size());
  const std::size_t count = meshopt_simplify(destination.data(), welded.data(), welded.size(), &mesh.positions[0].x,
                                             mesh.vertexCount(), sizeof(glm::vec3), target * 3, FLT_MAX, 0, nullptr);
  MeshLevelIndices out;
  out.indices.assign(destination.begin(), destination.begin() + std::ptrdiff_t(count));
  out.triangles.resize(count / 3);
  return out;
}

double diagonalOf(const SkinnedMesh& mesh) {
  glm::vec3 lo(FLT_MAX), hi(-FLT_MAX);
  for (const glm::vec3& p : mesh.positions)
    lo = glm::min(lo, p), hi = glm::max(hi, p);
  return double(glm::length(hi - lo));
}

// Best of `repeats` runs, in milliseconds of this thread's CPU time (the machines these run
// on are shared: wall time measures the neighbours too).
template <typename F> double millisecondsOf(F&& f, int repeats = 5) {
  const auto now = [] {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
  };
  double best = 1e30;
  for (int r = 0; r < repeats; ++r) {
    const double start = now();
    f();
    best = std::min(best, now() - start);
  }
  return best;
}

void compare(const std::string& path, double unitScale) {
  const Asset asset = importOrExit(path, unitScale);
  const SkinnedMesh* mesh = characterMesh(asset);
  if (!mesh) {
    std::printf("%s: no mesh\n", path.c_str());
    return;
  }
  const Skeleton* skeleton = mesh->skinned() && !asset.skeleton.empty() ? &asset.skeleton : nullptr;
  Result<MeshLod> lod =
      MeshLod::build(*mesh, skeleton, skeleton ? std::span<const Clip>(asset.clips) : std::span<const Clip>());
  if (!lod) {
    std::printf("%s: %s\n", path.c_str(), lod.message().c_str());
    return;
  }
  const double diagonal = diagonalOf(*mesh);
  const ProgressiveMesh& pm = lod->progressive();
  const std::vector<std::uint32_t> weld = positionWeld(*mesh);
  const double buildMs = millisecondsOf([&] {
    const std::vector<float> importance = vertexImportance(*mesh, {});
    benchmark::DoNotOptimize(ProgressiveMesh::build(*mesh, lod->simplifyPoses(), importance));
  });
  std::printf("\n%s: %zu triangles, %d welded vertices (%d locked), diagonal %.1f cm; simplified over bind + %zu "
              "poses, measured in bind + %zu other poses; ours: %.1f ms for every level\n",
              path.c_str(), mesh->triangleCount(), pm.weldedVertexCount(), pm.lockedCount(), diagonal,
              lod->simplifyPoses().size() - 1, lod->measurePoses().size(), buildMs);
  std::printf("%6s | %-49s | %-49s | %s\n", "ratio", "ours: tris  bind cm (%diag)  anim max (%)  anim mean",
              "meshopt: tris  bind cm (%diag)  anim max (%)  anim mean", "ms meshopt");
  for (double ratio : {0.5, 0.25, 0.1}) {
    const std::size_t target =
        std::max<std::size_t>(1, std::size_t(std::llround(ratio * double(mesh->triangleCount()))));
    const MeshLevelIndices ours = pm.level(pm.collapsesFor(target));
    const MeshLevelIndices theirs = meshoptLevel(*mesh, weld, target);
    const double theirMs = millisecondsOf([&] { benchmark::DoNotOptimize(meshoptLevel(*mesh, weld, target)); });
    const MeshLod::Errors a = lod->errorsOf(ours), b = lod->errorsOf(theirs);
    const auto pct = [&](double cm) { return diagonal > 0.0 ? 100.0 * cm / diagonal : 0.0; };
    std::printf("%6.2f | %10zu %7.3f (%5.2f) %7.3f (%5.2f) %7.3f | %13zu %7.3f (%5.2f) %7.3f (%5.2f) %7.3f | %6.2f\n",
                ratio, ours.triangles.size(), a.bindCm, pct(a.bindCm), a.animatedMaxCm, pct(a.animatedMaxCm),
                a.animatedMeanCm, theirs.indices.size() / 3, b.bindCm, pct(b.bindCm), b.animatedMaxCm,
                pct(b.animatedMaxCm), b.animatedMeanCm, theirMs);
    // meshopt may stop short of the target (its borders and seams are walls): the errors
    // above are then of different triangle counts, so compare ours at the count it reached
    const std::size_t reached = theirs.indices.size() / 3;
    if (double(reached) > 1.05 * double(target)) {
      const MeshLevelIndices same = pm.level(pm.collapsesFor(reached));
      const MeshLod::Errors c = lod->errorsOf(same);
      std::printf("       | %10zu %7.3f (%5.2f) %7.3f (%5.2f) %7.3f | ours at meshopt's count: it stopped at "
                  "%zu of %zu asked\n",
                  same.triangles.size(), c.bindCm, pct(c.bindCm), c.animatedMaxCm, pct(c.animatedMaxCm),
                  c.animatedMeanCm, reached, target);
    }
  }
}

void printComparisons() {
  const char* files = std::getenv("MLOD_MESHLOD_FILES");
  if (!files) {
    compare(std::string(MLOD_ASSIMP_MODELS) + "/X/BCN_Epileptic.X", 100.0);
    std::printf("\n");
    return;
  }
  std::istringstream list(files);
  std::string entry;
  while (list >> entry) {
    const std::size_t colon = entry.rfind(':');
    if (colon != std::string::npos && colon > 0)
      compare(entry.substr(0, colon), std::atof(entry.substr(colon + 1).c_str()));
    else
      compare(entry, 0.0);
  }
  std::printf("\n");
}

// A skinned tube of about `triangles` triangles bending at its middle joint, and its poses:
// the synthetic character of the speed goals.
struct Synthetic {
  test::Tube tube;
  std::vector<std::vector<glm::vec3>> poses;
};

const Synthetic& synthetic(int triangles) {
  static std::map<int, std::unique_ptr<Synthetic>> cache;
  auto& entry = cache[triangles];
  if (!entry) {
    entry = std::make_unique<Synthetic>();
    const int sides = triangles >= 20000 ? 100 : 32;
    const int rings = triangles / (2 * sides) + 1;
    entry->tube = test::makeTube(rings, sides, 40.0f / float(rings - 1));
    const Clip bend = test::tubeBendClip(entry->tube.skeleton, 24, 90.0f);
    Result<MeshLod> lod = MeshLod::build(entry->tube.mesh, &entry->tube.skeleton, std::span<const Clip>(&bend, 1));
    entry->poses = lod->simplifyPoses();
  }
  return *entry;
}

// The whole simplification and the level at 25%: what one level costs.
void BM_OursLevel(benchmark::State& state, const SkinnedMesh& mesh, const std::vector<std::vector<glm::vec3>>& poses) {
  std::size_t triangles = 0;
  for (auto _ : state) {
    const ProgressiveMesh pm = ProgressiveMesh::build(mesh, poses);
    const MeshLevelIndices level = pm.level(pm.collapsesFor(mesh.triangleCount() / 4));
    triangles = level.triangles.size();
    benchmark::DoNotOptimize(level);
  }
  state.counters["triangles_in"] = double(mesh.triangleCount());
  state.counters["triangles_out"] = double(triangles);
  state.counters["poses"] = double(poses.size());
}

void BM_MeshoptLevel(benchmark::State& state, const SkinnedMesh& mesh) {
  const std::vector<std::uint32_t> weld = positionWeld(mesh);
  std::size_t triangles = 0;
  for (auto _ : state) {
    const MeshLevelIndices level = meshoptLevel(mesh, weld, mesh.triangleCount() / 4);
    triangles = level.indices.size() / 3;
    benchmark::DoNotOptimize(level);
  }
  state.counters["triangles_in"] = double(mesh.triangleCount());
  state.counters["triangles_out"] = double(triangles);
}

void registerBenchmarks() {
  static const std::vector<std::vector<glm::vec3>> bcnPoses = [] {
    const Asset& asset = bcn();
    Result<MeshLod> lod = MeshLod::build(asset.meshes.at(0), &asset.skeleton, asset.clips);
    return lod->simplifyPoses();
  }();
  benchmark::RegisterBenchmark("BM_OursLevel/BCN_Epileptic", [](benchmark::State& s) {
    BM_OursLevel(s, bcn().meshes.at(0), bcnPoses);
  })->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("BM_MeshoptLevel/BCN_Epileptic", [](benchmark::State& s) {
    BM_MeshoptLevel(s, bcn().meshes.at(0));
  })->Unit(benchmark::kMillisecond);
  for (int triangles : {5000, 50000}) {
    const std::string name = "/tube" + std::to_string(triangles / 1000) + "k";
    benchmark::RegisterBenchmark(("BM_OursLevel" + name).c_str(), [triangles](benchmark::State& s) {
      BM_OursLevel(s, synthetic(triangles).tube.mesh, synthetic(triangles).poses);
    })->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("BM_MeshoptLevel" + name).c_str(), [triangles](benchmark::State& s) {
      BM_MeshoptLevel(s, synthetic(triangles).tube.mesh);
    })->Unit(benchmark::kMillisecond);
  }
}

} // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv))
    return 1;
  printComparisons();
  registerBenchmarks();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
