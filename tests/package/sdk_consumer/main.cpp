// Links the installed mlod::runtime and selects LOD levels for a small crowd: three characters
// at 1 m, 10 m and 50 m with switches at 5 m and 20 m must get levels 0, 1 and 2.
#include <runtime/lod_selection.h>

#include <array>
#include <cstdint>
#include <cstdio>

int main() {
  const std::array<glm::vec3, 3> positions{glm::vec3(100, 0, 0), glm::vec3(0, 0, 1000), glm::vec3(0, 5000, 0)};
  const std::array<float, 2> switchDistances{500.0f, 2000.0f};
  std::array<std::int32_t, 3> levels{-1, -1, -1};
  mlod::LodSelectionJob job;
  job.positions = positions;
  job.boundaries = switchDistances;
  job.inout_levels = levels;
  if (!job.validate() || !job.run()) {
    std::fprintf(stderr, "error: LodSelectionJob refused a valid crowd\n");
    return 1;
  }
  std::printf("levels %d %d %d\n", levels[0], levels[1], levels[2]);
  return levels == std::array<std::int32_t, 3>{0, 1, 2} ? 0 : 1;
}
