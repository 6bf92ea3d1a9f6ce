// The runtime bundle of a real LodPackage read back: the pose evaluator (and skinning) on
// the read-back clips gives bit-identical model matrices and palettes to the evaluator on
// the package's in-memory LodClips, at every level, for 0 and 4 blend frames, on CMU 01_01
// and BCN_Epileptic; each clip's bytes in the file are within 10% of its run-time bytes.

#include "core/lod/lod_package.h"
#include "core/lod_clip_builder.h"
#include "runtime/bundle.h"
#include "unit/package_fixtures.h"
#include "runtime/pose_evaluator.h"

#include <gtest/gtest.h>

#include <cstring>
#include <string>

namespace mlod {
namespace {

// Models and palettes of `clip` for several characters at spread times.
void evaluate(const LodClip& clip, std::span<const std::int16_t> parents, std::span<const glm::mat4> inverseBinds,
              int blendFrames, std::vector<glm::mat4>& models, std::vector<glm::mat4>& palette) {
  const int characters = 7;
  const int joints = static_cast<int>(parents.size());
  PoseEvaluatorContext context(characters, joints);
  std::vector<const LodClip*> clips(characters, &clip);
  models.assign(std::size_t(characters * joints), glm::mat4(0.0f));
  palette.assign(std::size_t(characters * joints), glm::mat4(0.0f));
  std::vector<double> times(characters);
  std::vector<glm::mat4> frameModels, framePalette;
  for (int step = 0; step < 40; ++step) { // stepping forward: held keys, cursors, blends
    for (int c = 0; c < characters; ++c)
      times[std::size_t(c)] = std::min(clip.duration(), clip.duration() * (double(c) / characters + step * 0.013));
    PoseEvaluatorJob job;
    job.parents = parents;
    job.inverseBinds = inverseBinds;
    job.clips = clips;
    job.times = times;
    job.blendFrames = blendFrames;
    job.context = &context;
    job.out_models = models;
    job.out_palette = palette;
    ASSERT_TRUE(job.run());
    frameModels.insert(frameModels.end(), models.begin(), models.end());
    framePalette.insert(framePalette.end(), palette.begin(), palette.end());
  }
  models = std::move(frameModels);
  palette = std::move(framePalette);
}

// The bundle of `package` for `blendFrames`, written and read: each read clip is the clip
// the package builds for that N, bit for bit (storage, bytes, and what the evaluator and
// skinning give), and its bytes in the file are within 10% of what it holds at run time.
void checkRoundTrip(const LodPackage& package, int blendFrames) {
  SCOPED_TRACE("blend frames " + std::to_string(blendFrames));
  Result<Bundle> bundle = packageBundle(package, BundleOptions{blendFrames});
  ASSERT_TRUE(bundle) << bundle.message();
  std::string error;
  const std::vector<std::uint8_t> bytes = writeBundle(*bundle, &error);
  ASSERT_FALSE(bytes.empty()) << error;
  std::optional<Bundle> read = readBundle(bytes, &error);
  ASSERT_TRUE(read) << error;
  ASSERT_EQ(read->levels.size(), package.levels.size());
  EXPECT_EQ(writeBundle(*read), bytes);
  for (std::size_t l = 0; l < package.levels.size(); ++l) {
    const LodPackageLevel& level = package.levels[l];
    const BundleLevel& readLevel = read->levels[l];
    SCOPED_TRACE("level " + level.settings.name);
    std::optional<BundleLevelRuntime> runtime = buildBundleLevel(readLevel, &error);
    ASSERT_TRUE(runtime) << error;
    ASSERT_EQ(runtime->clips.size(), level.runtimeClips.size());
    const std::vector<std::int16_t> parents = level.skeleton().parentIndices();
    EXPECT_EQ(readLevel.parents, parents);
    ASSERT_EQ(readLevel.inverseBinds.size(), level.inverseBinds.size());
    EXPECT_EQ(std::memcmp(readLevel.inverseBinds.data(), level.inverseBinds.data(),
                          level.inverseBinds.size() * sizeof(glm::mat4)), 0);
    for (std::size_t c = 0; c < level.runtimeClips.size(); ++c) {
      // what the engine would build from the package for this N
      const ClusterSet& clusters = level.runtimeClusters[c];
      Result<LodClip> built = buildLodClip(level.build.motion.clips[c], clusters.jointCount() > 0 ? &clusters : nullptr,
                                           std::nullopt, parents, blendFrames);
      ASSERT_TRUE(built) << built.message();
      const LodClip& memory = blendFrames == 0 ? level.runtimeClips[c] : *built;
      const LodClip& back = runtime->clips[c];
      EXPECT_EQ(back.clusterCount(), memory.clusterCount());
      EXPECT_EQ(back.byteSize(), memory.byteSize());
      EXPECT_EQ(back.blendFrames(), blendFrames);
      // the file holds what the evaluator reads, within 10%
      const double inFile = double(bundleClipBytes(readLevel.clips[c]));
      EXPECT_NEAR(inFile / double(back.byteSize()), 1.0, 0.1) << inFile << " bytes in the file, " << back.byteSize()
                                                               << " at run time";
      std::vector<glm::mat4> modelsA, paletteA, modelsB, paletteB;
      evaluate(memory, parents, level.inverseBinds, blendFrames, modelsA, paletteA);
      evaluate(back, readLevel.parents, readLevel.inverseBinds, blendFrames, modelsB, paletteB);
      ASSERT_EQ(modelsA.size(), modelsB.size());
      EXPECT_EQ(std::memcmp(modelsA.data(), modelsB.data(), modelsA.size() * sizeof(glm::mat4)), 0);
      EXPECT_EQ(std::memcmp(paletteA.data(), paletteB.data(), paletteA.size() * sizeof(glm::mat4)), 0);
      if (runtime->mesh && blendFrames == 0) { // skinning the read mesh with the read palette: the same vertices
        const SkinnedMesh* mesh = level.mesh();
        ASSERT_NE(mesh, nullptr);
        std::optional<SkinningMesh> memoryMesh =
            SkinningMesh::build(mesh->positions, mesh->normals, mesh->joints, mesh->weights, int(parents.size()));
        ASSERT_TRUE(memoryMesh);
        const std::size_t v = std::size_t(memoryMesh->vertexCount());
        std::vector<glm::vec3> pa(v), na(v), pb(v), nb(v);
        const std::span<const glm::mat4> first(paletteA.data(), parents.size());
        const std::span<const glm::mat4> firstB(paletteB.data(), parents.size());
        ASSERT_TRUE(memoryMesh->skin(first, pa, na));
        ASSERT_TRUE(runtime->mesh->skin(firstB, pb, nb));
        EXPECT_EQ(std::memcmp(pa.data(), pb.data(), v * sizeof(glm::vec3)), 0);
        EXPECT_EQ(std::memcmp(na.data(), nb.data(), v * sizeof(glm::vec3)), 0);
      }
    }
  }
}

void checkRoundTrip(const LodPackage& package) {
  checkRoundTrip(package, 0);
  checkRoundTrip(package, kDefaultBundleBlendFrames);
}

TEST(BundleRoundTrip, Cmu0101EvaluatesIdentically) {
  const LodPackage& package = test::realPackage("BVH/01_01.bvh", 2.54 / 0.45);
  ASSERT_EQ(package.levels.size(), 4u);
  checkRoundTrip(package);
}

TEST(BundleRoundTrip, BcnEpilepticEvaluatesAndSkinsIdentically) {
  const LodPackage& package = test::realPackage("X/BCN_Epileptic.X", 100.0);
  ASSERT_TRUE(package.mesh);
  checkRoundTrip(package);
}

TEST(BundleRoundTrip, CoarserLevelsTakeFewerBytes) {
  const LodPackage& package = test::realPackage("BVH/01_01.bvh", 2.54 / 0.45);
  Result<Bundle> bundle = packageBundle(package);
  ASSERT_TRUE(bundle);
  std::vector<std::size_t> sizes;
  for (const BundleLevel& level : bundle->levels) {
    Bundle one = *bundle;
    one.levels = {level};
    sizes.push_back(writeBundle(one).size());
  }
  // clustered frames are stored once per cluster, removed joints not at all
  ASSERT_EQ(sizes.size(), 4u);
  const std::size_t finest = sizes.at(0), coarsest = sizes.at(3);
  EXPECT_LT(coarsest, finest) << finest << " -> " << coarsest;
}

} // namespace
} // namespace mlod
