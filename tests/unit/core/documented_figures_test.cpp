// The figures docs/user-guide.md quotes for the bundled CMU sample (Table 1: simplified % and
// the max joint position error in cm at E = 5, 50, 100, 300), checked two ways: core's
// simplifyClip() reports them, and an independent forward kinematics written here from the
// clip's raw tracks and the cluster sets (a frozen joint takes its key frame's rotation)
// gives the same displacement. If the algorithm changes a figure, this fails and the guide
// (and scripts/check-docs-figures.sh) must be updated with it.

#include "core/jpc/jpc.h"
#include "io/importer.h"

#include <glm/gtc/quaternion.hpp>
#include <glm/gtx/quaternion.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

namespace mlod {
namespace {

const Asset& documentedSample() {
  static const Asset asset = [] {
    ImportOptions options;
    options.unitScale = *parseUnitScale("cmu");
    Result<Asset> imported = importAsset(std::string(MLOD_SOURCE_DIR) + "/resources/sample/cmu_01_01_excerpt.bvh", options);
    if (!imported)
      throw std::runtime_error(imported.message());
    return std::move(imported).value();
  }();
  return asset;
}

// Model-space joint positions at `frame`, from the raw tracks: model_j = model_parent x
// T(translation_j) x R(rotation_j) x S(scale_j); `rotationFrame(j)` says which frame's
// rotation joint j takes (the frame itself for the original, the key inside a cluster).
template <typename RotationFrame>
std::vector<glm::dvec3> positions(const Skeleton& skeleton, const Clip& clip, int frame, RotationFrame rotationFrame) {
  const int n = skeleton.jointCount();
  std::vector<glm::dmat4> models(static_cast<std::size_t>(n));
  std::vector<glm::dvec3> out(static_cast<std::size_t>(n));
  for (int j = 0; j < n; ++j) {
    const glm::dquat q(clip.rotation(j, rotationFrame(j)));
    glm::dmat4 local = glm::translate(glm::dmat4(1.0), glm::dvec3(clip.translation(j, frame))) * glm::mat4_cast(q) *
                       glm::scale(glm::dmat4(1.0), glm::dvec3(clip.scale(j, frame)));
    const int parent = skeleton.joints[static_cast<std::size_t>(j)].parent;
    models[static_cast<std::size_t>(j)] = parent < 0 ? local : models[static_cast<std::size_t>(parent)] * local;
    out[static_cast<std::size_t>(j)] = glm::dvec3(models[static_cast<std::size_t>(j)][3]);
  }
  return out;
}

struct Documented {
  double threshold;
  double simplifiedPercent; // rounded to 0.1 in the guide
  double maxErrorCm;        // rounded to 0.001 in the guide
};

// docs/user-guide.md, "Reading Table 1 and the charts".
const Documented kGuide[] = {{5.0, 39.4, 0.116}, {50.0, 77.6, 1.626}, {100.0, 87.2, 4.164}, {300.0, 97.0, 9.121}};

TEST(DocumentedFigures, SampleTable1AgreesWithIndependentForwardKinematics) {
  const Asset& asset = documentedSample();
  const Clip& clip = asset.clips.front();
  ASSERT_EQ(clip.frameCount, 480); // "480 frames at 120 fps"
  JpcSettings settings;
  settings.zeroLength = 1e-6 * asset.unitScale;
  std::vector<double> thresholds;
  for (const Documented& row : kGuide)
    thresholds.push_back(row.threshold);
  Result<std::vector<JpcLevelResult>> levels = simplifyClip(asset.skeleton, clip, settings, thresholds, 1);
  ASSERT_TRUE(levels.ok()) << levels.message();

  for (std::size_t i = 0; i < std::size(kGuide); ++i) {
    SCOPED_TRACE("E = " + std::to_string(kGuide[i].threshold));
    const JpcLevelResult& level = (*levels)[i];
    EXPECT_NEAR(level.simplifiedPercent, kGuide[i].simplifiedPercent, 0.05);
    EXPECT_NEAR(level.maxJointPositionErrorCm, kGuide[i].maxErrorCm, 0.0005);

    // The same figure without core's simplified-motion code: each joint's key per frame
    // from the cluster set, positions by the FK above.
    std::vector<std::vector<int>> key(static_cast<std::size_t>(asset.skeleton.jointCount()));
    for (int j = 0; j < asset.skeleton.jointCount(); ++j) {
      std::vector<int>& frames = key[static_cast<std::size_t>(j)];
      frames.resize(static_cast<std::size_t>(clip.frameCount));
      for (int t = 0; t < clip.frameCount; ++t)
        frames[static_cast<std::size_t>(t)] = t;
      for (const Cluster& cluster : level.clusters.joints[static_cast<std::size_t>(j)])
        for (int t = cluster.first; t <= cluster.last; ++t)
          frames[static_cast<std::size_t>(t)] = cluster.key;
    }
    double maxCm = 0.0;
    for (int t = 0; t < clip.frameCount; ++t) {
      const std::vector<glm::dvec3> original = positions(asset.skeleton, clip, t, [t](int) { return t; });
      const std::vector<glm::dvec3> simplified =
          positions(asset.skeleton, clip, t, [&](int j) { return key[static_cast<std::size_t>(j)][static_cast<std::size_t>(t)]; });
      for (std::size_t j = 0; j < original.size(); ++j)
        maxCm = std::max(maxCm, glm::length(original[j] - simplified[j]));
    }
    EXPECT_NEAR(maxCm, kGuide[i].maxErrorCm, 0.0005);
    EXPECT_NEAR(maxCm, level.maxJointPositionErrorCm, 1e-3);
  }
}

} // namespace
} // namespace mlod
