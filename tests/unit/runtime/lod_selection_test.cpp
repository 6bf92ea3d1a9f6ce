// LOD selection by camera distance and by projected size, with hysteresis.

#include "runtime/lod_selection.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace mlod {
namespace {

const std::vector<float> kDistances{1000.0f, 2000.0f, 4000.0f}; // cm: 4 levels

// Guards the plain choice (no current level): the number of boundaries passed.
TEST(LodSelection, DistanceWithoutHistory) {
  EXPECT_EQ(selectLevelByDistance(0.0f, kDistances), 0);
  EXPECT_EQ(selectLevelByDistance(999.0f, kDistances), 0);
  EXPECT_EQ(selectLevelByDistance(1000.0f, kDistances), 1);
  EXPECT_EQ(selectLevelByDistance(3999.0f, kDistances), 2);
  EXPECT_EQ(selectLevelByDistance(1e9f, kDistances), 3);
  EXPECT_EQ(selectLevelByDistance(5.0f, {}), 0) << "one level";
}

// Guards hysteresis: a character walking out and back across a boundary switches late both
// ways, and one standing on the boundary keeps its level.
TEST(LodSelection, DistanceHysteresis) {
  const float h = 0.1f;
  int level = selectLevelByDistance(900.0f, kDistances);
  ASSERT_EQ(level, 0);
  level = selectLevelByDistance(1050.0f, kDistances, level, h);
  EXPECT_EQ(level, 0) << "past the boundary by less than 10%";
  level = selectLevelByDistance(1101.0f, kDistances, level, h);
  EXPECT_EQ(level, 1);
  level = selectLevelByDistance(950.0f, kDistances, level, h);
  EXPECT_EQ(level, 1) << "back inside by less than 10%";
  level = selectLevelByDistance(899.0f, kDistances, level, h);
  EXPECT_EQ(level, 0);
  // a jump across several boundaries moves several levels at once
  EXPECT_EQ(selectLevelByDistance(5000.0f, kDistances, 0, h), 3);
  EXPECT_EQ(selectLevelByDistance(10.0f, kDistances, 3, h), 0);
  // flickering around 1000 cm never switches
  level = 0;
  for (int i = 0; i < 100; ++i) {
    level = selectLevelByDistance(i % 2 ? 1040.0f : 960.0f, kDistances, level, h);
    EXPECT_EQ(level, 0);
  }
}

// Guards the projection: a sphere filling the view at the distance where the visible
// height equals its diameter covers the whole viewport.
TEST(LodSelection, ProjectedSize) {
  ScreenProjection projection;
  const float radius = 100.0f;
  const float fit = radius / std::tan(0.5f * projection.verticalFovRadians);
  EXPECT_NEAR(projectedSizePixels(radius, fit, projection), projection.viewportHeightPixels, 1e-2f);
  EXPECT_NEAR(projectedSizePixels(radius, 2.0f * fit, projection), projection.viewportHeightPixels / 2.0f, 1e-2f);
}

// Guards selection by size: smaller on screen is coarser, with hysteresis.
TEST(LodSelection, ScreenSizeHysteresis) {
  const std::vector<float> sizes{400.0f, 100.0f, 20.0f};
  EXPECT_EQ(selectLevelByScreenSize(1000.0f, sizes), 0);
  EXPECT_EQ(selectLevelByScreenSize(399.0f, sizes), 1);
  EXPECT_EQ(selectLevelByScreenSize(5.0f, sizes), 3);
  EXPECT_EQ(selectLevelByScreenSize(380.0f, sizes, 0, 0.1f), 0) << "below by less than 10%";
  EXPECT_EQ(selectLevelByScreenSize(359.0f, sizes, 0, 0.1f), 1);
  EXPECT_EQ(selectLevelByScreenSize(420.0f, sizes, 1, 0.1f), 1) << "above by less than 10%";
  EXPECT_EQ(selectLevelByScreenSize(441.0f, sizes, 1, 0.1f), 0);
}

// Guards the crowd job: each character from its own distance and current level; invalid
// jobs fail validate() and change no level.
TEST(LodSelection, CrowdJob) {
  const std::vector<glm::vec3> positions{{0, 0, 500}, {0, 0, 1050}, {0, 0, 3000}, {0, 0, 9000}};
  const std::vector<float> radii(positions.size(), 90.0f);
  std::vector<std::int32_t> levels{-1, 1, -1, 0};
  LodSelectionJob job;
  job.positions = positions;
  job.boundaries = kDistances;
  job.inout_levels = levels;
  ASSERT_TRUE(job.run());
  EXPECT_EQ(levels, (std::vector<std::int32_t>{0, 1, 2, 3}));

  LodSelectionJob bySize;
  bySize.mode = LodSelectionJob::Mode::ScreenSize;
  bySize.positions = positions;
  bySize.radii = radii;
  const std::vector<float> sizes{100.0f, 30.0f};
  bySize.boundaries = sizes;
  std::vector<std::int32_t> sizeLevels(positions.size(), -1);
  bySize.inout_levels = sizeLevels;
  ASSERT_TRUE(bySize.run());
  for (std::size_t c = 0; c < positions.size(); ++c)
    EXPECT_EQ(sizeLevels[c],
              selectLevelByScreenSize(projectedSizePixels(90.0f, glm::length(positions[c])), sizes))
        << "character " << c;
  EXPECT_LE(sizeLevels[0], sizeLevels[3]);

  std::vector<LodSelectionJob> invalid(6, job);
  const std::vector<float> descending{2000.0f, 1000.0f};
  invalid[0].boundaries = descending; // distances must ascend
  invalid[1].inout_levels = std::span<std::int32_t>(levels.data(), 2); // one level per character
  invalid[2].hysteresis = 1.0f;
  std::vector<std::int32_t> outOfRange{0, 0, 7, 0};
  invalid[3].inout_levels = outOfRange; // a level that does not exist
  invalid[4].mode = LodSelectionJob::Mode::ScreenSize; // no radii
  const std::vector<float> zero{0.0f, 1000.0f};
  invalid[5].boundaries = zero;
  const std::vector<std::int32_t> before = levels;
  for (std::size_t i = 0; i < invalid.size(); ++i) {
    EXPECT_FALSE(invalid[i].validate()) << "case " << i;
    EXPECT_FALSE(invalid[i].run()) << "case " << i;
  }
  EXPECT_EQ(levels, before);
}

} // namespace
} // namespace mlod
