#pragma once
// Plays every clip of every level of a read bundle through the pose evaluator, two
// characters at `steps` times across the clip (one of them counting down, one past the end
// of a looping clip), the way an engine reads the storage: under the sanitizer build and the
// bundle fuzzer, any read out of bounds stops the run. Returns the runs the evaluator
// accepted (a lying frame rate may make the times infinite: the job refuses those).

#include "runtime/bundle.h"
#include "runtime/pose_evaluator.h"

#include <algorithm>
#include <vector>

namespace mlod::test {

inline int playBundle(const Bundle& bundle, int steps) {
  int played = 0;
  for (const BundleLevel& level : bundle.levels) {
    const int joints = level.jointCount();
    PoseEvaluatorContext context(2, joints);
    std::vector<glm::mat4> models(std::size_t(2 * joints)), palette(std::size_t(2 * joints));
    for (const BundleClip& clip : level.clips) {
      const std::vector<const LodClip*> clips(2, &clip.clip);
      const double duration = clip.clip.duration();
      for (int step = 0; step < steps; ++step) {
        const double t = std::min(duration * step / std::max(steps - 1, 1), duration);
        const std::vector<double> times = {t, clip.clip.looping() ? duration + t : std::max(duration - t, 0.0)};
        PoseEvaluatorJob job;
        job.parents = level.parents;
        job.inverseBinds = level.inverseBinds;
        job.clips = clips;
        job.times = times;
        job.blendFrames = clip.clip.blendFrames();
        job.context = &context;
        job.out_models = models;
        job.out_palette = palette;
        played += job.run() ? 1 : 0;
      }
    }
  }
  return played;
}

} // namespace mlod::test
