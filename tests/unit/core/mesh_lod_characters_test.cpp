// Every skinned character of Debian's assimp-testmodels with at least 500 triangles reaches
// 50%, 25% and 10% of its triangles within 5% (issue 14's goal; 64 closed cubes stopped at
// 16.7% before components could be pruned). The characters are named (the shared fixture
// list, unit/real_files.h) and found: every file under MLOD_ASSIMP_MODELS that imports with a skinned mesh of >= 500
// triangles. A named one that does not import, or has no such mesh any more, fails the
// test, and so does one found that is not named: nothing is skipped in silence.

#include "core/mesh/mesh_lod.h"
#include "io/isolated_import.h"
#include "unit/real_files.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <gtest/gtest.h>
#include <string>
#include <vector>

namespace mlod {
namespace {

// note: pictures, texts and shaders beside the models are not tried (they are no models;
// importing them only costs time)
bool mayBeModel(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  for (const char* skipped : {".png", ".jpg", ".jpeg", ".tga",  ".bmp", ".dds", ".gif", ".tif", ".tiff", ".pcx", ".psd",
                              ".txt", ".md",  ".mtl",  ".glsl", ".bin", ".xml", ".ini", ".zip", ".lws",  ""})
    if (extension == skipped)
      return false;
  return true;
}

TEST(MeshLodCharacters, EverySkinnedCharacterReachesFiftyTwentyFiveAndTenPercent) {
  namespace fs = std::filesystem;
  const fs::path root(MLOD_ASSIMP_MODELS);
  ASSERT_TRUE(fs::is_directory(root)) << root << " is not installed (assimp-testmodels)";
  const std::vector<std::string> characters = test::fixtureCharacters();
  ASSERT_GE(characters.size(), 5u) << "tests/data/expected_counts.json names no characters";
  std::vector<fs::path> files;
  for (const fs::directory_entry& entry : fs::recursive_directory_iterator(root))
    if (entry.is_regular_file() && mayBeModel(entry.path()))
      files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  std::vector<std::string> found;
  for (const fs::path& file : files) {
    // note: isolated, as the command line reads files: some of these make Assimp allocate
    // gigabytes in-process
    IsolationLimits limits;
    limits.timeoutSeconds = 30.0;
    limits.memoryBytes = std::size_t{2} << 30;
    const std::string name = fs::relative(file, root).string();
    const bool named = std::find(characters.begin(), characters.end(), name) != characters.end();
    Result<Asset> asset = importAssetIsolated(file.string(), {}, limits);
    if (named) {
      EXPECT_TRUE(asset) << name << " no longer imports: " << asset.message();
    }
    if (!asset || asset->skeleton.empty())
      continue;
    for (const SkinnedMesh& mesh : asset->meshes) {
      if (!mesh.skinned() || mesh.triangleCount() < 500)
        continue;
      SCOPED_TRACE(file.string() + " mesh '" + mesh.name + "'");
      found.push_back(name);
      EXPECT_TRUE(named) << name << " is a skinned character of >= 500 triangles that the fixture list does not name";
      Result<MeshLod> lod = MeshLod::build(mesh, &asset->skeleton, asset->clips);
      ASSERT_TRUE(lod) << lod.message();
      const ProgressiveMesh& pm = lod->progressive();
      for (double ratio : {0.5, 0.25, 0.1}) {
        const double target = ratio * double(mesh.triangleCount());
        const std::size_t reached = pm.trianglesAfter(pm.collapsesFor(std::size_t(std::llround(target))));
        EXPECT_LE(std::abs(double(reached) - target), 0.05 * target)
            << "ratio " << ratio << ": " << reached << " of " << mesh.triangleCount() << " triangles";
        const MeshLevelIndices level = pm.level(pm.collapsesFor(std::size_t(std::llround(target))));
        EXPECT_EQ(level.triangles.size(), reached);
      }
    }
  }
  for (const std::string& name : characters)
    EXPECT_NE(std::find(found.begin(), found.end(), name), found.end())
        << name << " was not found as a skinned character of >= 500 triangles";
}

} // namespace
} // namespace mlod
